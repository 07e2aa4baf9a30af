#include "hapsim/servo/pose_deadband.h"

#include <cmath>

namespace hapsim::bridge {

PoseDeadband::PoseDeadband(const PoseDeadbandConfig& config)
    : config_(config), keepalive_ns_(static_cast<std::int64_t>(std::llround(config.keepalive_s * 1e9))) {}

bool PoseDeadband::Offer(const SensedPose& pose) {
  bool send = config_.position_m <= 0.0 || !have_sent_ || pose.tool.buttons != sent_.tool.buttons ||
              pose.t_device_ns - sent_.t_device_ns >= keepalive_ns_;
  if (!send) {
    const double since_s = static_cast<double>(pose.t_device_ns - sent_.t_device_ns) * 1e-9;
    const Eigen::Vector3d predicted_m = sent_.tool.tip_W_m + since_s * sent_.tool.velocity_W_m_per_s;
    // Written so that a NaN anywhere sends (the server refuses it, and says so).
    send = !((pose.tool.tip_W_m - predicted_m).norm() <= config_.position_m) ||
           !((pose.tool.velocity_W_m_per_s - sent_.tool.velocity_W_m_per_s).norm() <= config_.velocity_m_per_s);
  }
  if (send) {
    sent_ = pose;
    have_sent_ = true;
  }
  return send;
}

}  // namespace hapsim::bridge
