#include "hapsim/runtime/model_deadband.h"

#include <algorithm>
#include <cmath>

namespace hapsim::service {

ModelDeadband::ModelDeadband(const ModelDeadbandConfig& config)
    : config_(config), keepalive_ns_(static_cast<std::int64_t>(std::llround(config.keepalive_s * 1e9))) {}

bool ModelDeadband::Differs(const core::LocalForceModel& model, const core::ToolInput& tool) const {
  if (model.state != sent_.state) return true;
  const Eigen::Vector3d& x = tool.tip_W_m;
  const Eigen::Vector3d& v = tool.velocity_W_m_per_s;
  const Eigen::Vector3d inside = x - config_.probe_depth_m * model.normal_W;
  for (const Eigen::Vector3d& at : {x, inside}) {
    const Eigen::Vector3d now_N = core::EvaluateLocalForce(model, at, v);
    const Eigen::Vector3d held_N = core::EvaluateLocalForce(sent_, at, v);
    const double felt_N = std::max({now_N.norm(), held_N.norm(), config_.floor_N});
    if (!((now_N - held_N).norm() <= config_.jnd * felt_N)) return true;  // NaN: send (the bridge refuses it)
  }
  return false;
}

bool ModelDeadband::Offer(const core::LocalForceModel& model, const core::ToolInput& tool, std::int64_t now_ns) {
  if (config_.jnd <= 0.0) return true;  // every tick: nothing to remember
  const bool send = !have_sent_ || now_ns - sent_ns_ >= keepalive_ns_ || Differs(model, tool);
  if (send) {
    sent_ = model;
    sent_ns_ = now_ns;
    have_sent_ = true;
  }
  return send;
}

}  // namespace hapsim::service
