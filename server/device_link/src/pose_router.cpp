#include "hapsim/device_link/pose_router.h"

#include <spdlog/spdlog.h>

#include <optional>

namespace hapsim::service {

namespace {

// The checks before the session sees a sample: the pose filter, then the
// sample's own session field. The tool input, or nothing (counted, warned).
std::optional<core::ToolInput> PoseForThisPartition(Session& session, const hapsim_dds_StylusPose& sample,
                                                    const PoseLimits& limits, std::int64_t now,
                                                    ServerDdsCounters* counters, WarningLimiter* warnings) {
  PoseRejection why = PoseRejection::kNone;
  auto tool = FilterPose(sample, limits, &why);
  if (!tool) {
    counters->poses_rejected.fetch_add(1);
    session.counters().poses.rejected.fetch_add(1);
    if (warnings->Due(now)) {
      spdlog::warn("dropped a pose from device {} (session '{}'): {}", sample.device_id, session.id(), ToString(why));
    }
    return std::nullopt;
  }
  if (SessionIdOf(sample.session) != session.id()) {
    counters->poses_wrong_session.fetch_add(1);
    session.counters().poses.wrong_session.fetch_add(1);
    if (warnings->Due(now)) {
      spdlog::warn("pose from device {} naming session '{}' arrived in the partition of session '{}': dropped",
                   sample.device_id, SessionIdOf(sample.session), session.id());
    }
    return std::nullopt;
  }
  return tool;
}

// The session's own checks (device ownership, seq); true if it took the pose.
bool OfferPoseToSession(Session& session, const hapsim_dds_StylusPose& sample, const core::ToolInput& tool,
                        std::int64_t now, ServerDdsCounters* counters, WarningLimiter* warnings) {
  const PoseVerdict verdict = session.OfferPose(PoseSample{tool, sample.device_id, sample.seq, now});
  if (verdict == PoseVerdict::kOtherDevice) {
    counters->poses_other_device.fetch_add(1);
    if (warnings->Due(now)) {
      spdlog::warn("pose from device {} for session '{}' dropped: device {} drives it", sample.device_id, session.id(),
                   session.counters().tick.owning_device_id.load());
    }
    return false;
  }
  if (verdict == PoseVerdict::kStale) {
    counters->poses_stale.fetch_add(1);
    if (warnings->Due(now)) {
      spdlog::warn(
          "pose seq {} from device {} for session '{}' dropped as stale (duplicate, reordered, or a "
          "second bridge with the same device id)",
          sample.seq, sample.device_id, session.id());
    }
    return false;
  }
  counters->poses_accepted.fetch_add(1);
  return true;
}

}  // namespace

bool RoutePoseBatch(Session& session, std::span<const hapsim_dds_StylusPose> batch, const PoseLimits& limits,
                    std::int64_t now, ServerDdsCounters* counters, WarningLimiter* warnings) {
  bool offered = false;
  for (const auto& sample : batch) {
    const auto tool = PoseForThisPartition(session, sample, limits, now, counters, warnings);
    if (tool && OfferPoseToSession(session, sample, *tool, now, counters, warnings)) offered = true;
  }
  return offered;
}

}  // namespace hapsim::service
