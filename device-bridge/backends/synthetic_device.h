// Synthetic device: scripted tool motion for demos, tests and load tests, no
// hardware needed. The tool is held vertical (identity orientation: the
// needle points down -z) above the tissue surface at z = 0.
//
// Scripts (positions of the tip, world frame):
//  insertion       approach from start height to the surface, press to
//                  depth_m at speed, hold for hold_s, withdraw to the start
//                  height; repeats until the run ends.
//  constant_speed  one constant-speed insertion to depth_m and back out at
//                  the same speed (the acupuncture force-depth experiment).
//  random_walk     bounded, seeded random walk of the tip around the
//                  surface (palpation-like noise; deterministic per seed).
//  hold            the tip stays at the start height (no contact).
//  cut             a scalpel stroke, once: approach the entry point, press
//                  to depth_m, draw an incision of cut_length_m heading
//                  cut_angle_rad (bending by cut_bend_rad along it: 0 is
//                  straight), lift to the start height, rest ("done"). The
//                  blade leans back against the stroke by blade_tilt_rad.
#pragma once
#include <cstdint>
#include <random>
#include <string>

#include "hapsim/servo/device.h"

namespace hapsim::bridge {

struct SyntheticScript {
  std::string kind = "insertion";
  Eigen::Vector3d entry_W_m = Eigen::Vector3d::Zero();  // point on the surface above which the tip moves
  double start_height_m = 0.01;   // height above the surface where a cycle starts
  double depth_m = 0.005;         // deepest point below the surface
  double speed_m_per_s = 0.01;    // approach/press/withdraw speed
  double hold_s = 0.5;            // pause at depth (insertion)
  // Random-walk step per 1 ms tick, per axis (std dev): 30 um, a hand's
  // palpating speed (mean ~48 mm/s), well under the chain's 0.6 m/s velocity
  // limit (a 0.5 mm step would be ~0.8 m/s: past it, no force at all).
  double walk_step_m = 0.00003;
  double walk_radius_m = 0.01;    // random-walk bound around the entry point
  std::uint32_t seed = 1;
  double cut_length_m = 0.02;     // cut: incision length
  double cut_angle_rad = 0.0;     // cut: initial heading in the skin plane (0: +x)
  double cut_bend_rad = 0.0;      // cut: heading change over the incision (an arc)
  double blade_tilt_rad = 0.5236; // cut: blade leaning back from vertical (30°)
};

// Throws std::invalid_argument naming the first field out of range (speed,
// depth, heights, hold time, cut geometry, unknown kind).
void ValidateSyntheticScript(const SyntheticScript& script);

class SyntheticDevice final : public HapticDevice {
 public:
  explicit SyntheticDevice(SyntheticScript script);  // throws std::invalid_argument (ValidateSyntheticScript)
  std::string Name() const override { return "synthetic/" + script_.kind; }
  DeviceReading Read(double t_s) override;
  void CommandForce(const Eigen::Vector3d& force_W_N) override { last_force_W_N_ = force_W_N; }
  const Eigen::Vector3d& last_force_W_N() const { return last_force_W_N_; }

  // Height of the tip relative to the surface [m] and phase at time t of the
  // insertion / constant-speed scripts (pure; used by Read and by tests).
  static double ScriptHeight(const SyntheticScript& s, double t_s, const char** phase, double* vz);
  // The cut script's tip, velocity and orientation at time t (pure).
  static DeviceReading CutPose(const SyntheticScript& s, double t_s);

 private:
  SyntheticScript script_;
  Eigen::Vector3d last_force_W_N_ = Eigen::Vector3d::Zero();
  std::mt19937 rng_;
  Eigen::Vector3d walk_W_m_ = Eigen::Vector3d::Zero();
  double last_t_s_ = 0.0;
};

}  // namespace hapsim::bridge
