// A haptic device as the servo loop sees it. Backends: synthetic (scripted
// motion, always built), replay (recorded pose log, always built) and
// OpenHaptics (Phantom Omni / Geomagic Touch, optional). Positions are in
// the world frame W in metres; a backend converts its native units (the HD
// API's mm) in one place.
#pragma once
#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hapsim::bridge {

struct DeviceReading {
  Eigen::Vector3d tip_W_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_W = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity_W_m_per_s = Eigen::Vector3d::Zero();
  std::uint32_t buttons = 0;
  // Backends with a script say which part of it is running ("approach",
  // "press", "hold", "withdraw", ...); empty for real devices.
  const char* phase = "";
  bool finished = false;  // a script or a replay has ended
};

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  virtual std::string Name() const = 0;
  // Called once per servo tick with the time since the loop started [s].
  // Must not block or allocate.
  virtual DeviceReading Read(double t_s) = 0;
  // The force to render until the next tick [N], already clamped by the
  // safety layer. Must not block or allocate.
  virtual void CommandForce(const Eigen::Vector3d& force_W_N) = 0;
};

}  // namespace hapsim::bridge
