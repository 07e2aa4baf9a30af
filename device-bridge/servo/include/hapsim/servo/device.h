// A haptic device as the servo loop sees it. Backends: synthetic (scripted
// motion, always built), replay (recorded pose log, always built) and
// OpenHaptics (Phantom Omni / Geomagic Touch, optional). Positions are in
// the world frame W in metres; a backend converts its native units (the HD
// API's mm) in one place.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "hapsim/servo/device_limits.h"

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
  // What the device says about its limits (0: unknown); the safety chain
  // combines them with its configured ones (CombineLimits).
  virtual DeviceLimits Limits() const { return {}; }
  // A device whose driver runs its own servo scheduler (OpenHaptics) calls
  // tick(t) once per scheduler tick, t the time since the loop started [s],
  // until tick returns false or stop is set, and returns only after its
  // last call to tick has returned (the loop reads the tick's results
  // then). Others return false from RunsOwnServo and the servo loop keeps
  // its own clock.
  virtual bool RunsOwnServo() const { return false; }
  virtual void RunServo(const std::function<bool(double t_s)>& /*tick*/, const std::atomic<bool>& /*stop*/) {}
};

}  // namespace hapsim::bridge
