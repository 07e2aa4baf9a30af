#include "hapsim/device_link/pose_filter.h"

#include <cmath>
#include <cstring>

#include "hapsim/wire/topics_wire.h"

namespace hapsim::service {

std::string_view ToString(PoseRejection r) {
  switch (r) {
    case PoseRejection::kNone: return "ok";
    case PoseRejection::kNotFinite: return "non-finite value";
    case PoseRejection::kPositionOutOfRange: return "position out of range";
    case PoseRejection::kSpeedOutOfRange: return "speed out of range";
    case PoseRejection::kBadQuaternion: return "orientation is not a unit quaternion";
    case PoseRejection::kBadSession: return "malformed session id";
  }
  return "unknown";
}

std::string_view SessionIdOf(const char (&field)[64]) {
  const void* nul = std::memchr(field, '\0', sizeof field);
  if (!nul) return {};
  return std::string_view(field, static_cast<std::size_t>(static_cast<const char*>(nul) - field));
}

std::optional<core::ToolInput> FilterPose(const hapsim_dds_StylusPose& pose, const PoseLimits& limits,
                                          PoseRejection* why) {
  *why = PoseRejection::kNone;
  if (SessionIdOf(pose.session).empty()) {
    *why = PoseRejection::kBadSession;
    return std::nullopt;
  }
  const Eigen::Vector3d p(pose.pos_m[0], pose.pos_m[1], pose.pos_m[2]);
  const Eigen::Vector3d v(pose.vel_m_per_s[0], pose.vel_m_per_s[1], pose.vel_m_per_s[2]);
  const Eigen::Vector4d q(pose.quat_wxyz[0], pose.quat_wxyz[1], pose.quat_wxyz[2], pose.quat_wxyz[3]);
  if (!p.allFinite() || !v.allFinite() || !q.allFinite()) {
    *why = PoseRejection::kNotFinite;
    return std::nullopt;
  }
  if (p.norm() > limits.max_distance_m) {  // distance from the origin, as docs/protocol.md states
    *why = PoseRejection::kPositionOutOfRange;
    return std::nullopt;
  }
  if (v.norm() > limits.max_speed_m_per_s) {
    *why = PoseRejection::kSpeedOutOfRange;
    return std::nullopt;
  }
  if (std::abs(q.norm() - 1.0) > limits.quaternion_norm_tolerance) {
    *why = PoseRejection::kBadQuaternion;
    return std::nullopt;
  }
  core::ToolInput tool = wire::UnpackPose(pose);
  tool.orientation_W.normalize();
  return tool;
}

}  // namespace hapsim::service
