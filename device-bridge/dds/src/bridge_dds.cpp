#include "hapsim/bridge/bridge_dds.h"

namespace hapsim::bridge {

BridgeDds::BridgeDds(const dds::Options& options, std::uint32_t device_id, std::string session)
    : router_(device_id, {std::move(session)}), dds_(options, &router_, [this] { WriteNewestPose(); }) {}

void BridgeDds::WriteNewestPose() {
  SensedPose pose;
  if (pose_outbox_.TakeIfNew(&pose) && dds_.WritePose(pose)) poses_written_.fetch_add(1);
}

}  // namespace hapsim::bridge
