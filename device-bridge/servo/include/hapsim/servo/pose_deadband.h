// Perceptual deadband for the poses a device sends (Hinterseer et al.): a
// pose goes out only when the server, extrapolating the last one sent along
// its velocity, would have the tool somewhere the force would differ — more
// than position_m away, or the velocity off by more than velocity_m_per_s —
// or when the buttons change, or as a keep-alive. The server extrapolates
// the same way (SessionConfig::pose_extrapolation_s), so a tool moving at
// constant velocity costs a keep-alive only. Runs in the servo tick;
// allocates nothing.
#pragma once
#include <cstdint>

#include "hapsim/servo/servo_messages.h"

namespace hapsim::bridge {

struct PoseDeadbandConfig {
  double position_m = 0.0;  // 0: every pose goes out
  double velocity_m_per_s = 0.005;
  double keepalive_s = 0.025;
};

class PoseDeadband {
 public:
  explicit PoseDeadband(const PoseDeadbandConfig& config);

  // Should this pose go out? Records it as sent if so.
  bool Offer(const SensedPose& pose);

 private:
  PoseDeadbandConfig config_;
  std::int64_t keepalive_ns_;
  bool have_sent_ = false;
  SensedPose sent_;
};

}  // namespace hapsim::bridge
