#include "hapsim/bridge/bridge_dds.h"

namespace hapsim::bridge {

BridgeDds::BridgeDds(const dds::Options& options, std::uint32_t first_device_id, std::vector<std::string> sessions)
    : router_(first_device_id, sessions),
      pose_outboxes_(std::make_unique<common::LatestValue<SensedPose>[]>(sessions.size())),
      poses_written_(std::make_unique<std::atomic<std::uint64_t>[]>(sessions.size())),
      dds_(options, &router_, [this] { WriteNewestPoses(); }) {}

void BridgeDds::WriteNewestPoses() {
  for (std::size_t i = 0; i < router_.devices(); ++i) {
    SensedPose pose;
    if (pose_outboxes_[i].TakeIfNew(&pose) && dds_.WritePose(pose)) poses_written_[i].fetch_add(1);
  }
}

}  // namespace hapsim::bridge
