// Replay device: plays back a recorded pose log (the CSV that
// `hapsim-bridge --trace FILE` writes, or any file with the same first
// columns): header line, then rows
//   t_s,x_m,y_m,z_m,qw,qx,qy,qz[,more columns ignored]
// with t_s strictly increasing. Positions are interpolated linearly between
// rows (orientation: normalised lerp); velocity is the row-to-row slope.
#pragma once
#include <string>
#include <vector>

#include "hapsim/servo/device.h"

namespace hapsim::bridge {

struct PoseLogRow {
  double t_s = 0.0;
  Eigen::Vector3d tip_W_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
};

// Throws std::invalid_argument naming the line for a malformed log.
std::vector<PoseLogRow> ParsePoseLog(const std::string& text);
std::vector<PoseLogRow> LoadPoseLog(const std::string& path);

class ReplayDevice final : public HapticDevice {
 public:
  explicit ReplayDevice(std::vector<PoseLogRow> rows);  // throws if empty
  std::string Name() const override { return "replay"; }
  DeviceReading Read(double t_s) override;
  void CommandForce(const Eigen::Vector3d&) override {}

 private:
  std::vector<PoseLogRow> rows_;
  std::size_t cursor_ = 0;  // rows_[cursor_].t_s <= t < rows_[cursor_+1].t_s
};

}  // namespace hapsim::bridge
