// The bridge's DDS adapter: a DeviceDds for the bridge's devices (one, or
// one per --device; ids first_device_id + i) whose I/O thread writes the
// newest pose each servo loop posts and takes the force models addressed to
// each device and session, stamping their arrival with the bridge's clock
// (Cyclone's lifespan QoS counts from local receive time, so age is
// measured here). One DDS participant for the whole process.
#pragma once
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/bridge/device_dds.h"
#include "hapsim/bridge/model_router.h"

namespace hapsim::bridge {

class BridgeDds {
 public:
  BridgeDds(const dds::Options& options, std::uint32_t first_device_id, std::vector<std::string> sessions);
  void Start() { dds_.Start(); }
  void Stop() { dds_.Stop(); }
  void Wake() { dds_.Wake(); }

  std::size_t devices() const { return router_.devices(); }
  // Device i's mailboxes: the servo loop's newest pose out, the newest model in.
  common::LatestValue<SensedPose>& pose_outbox(std::size_t i) { return pose_outboxes_[i]; }
  common::LatestValue<ReceivedModel>& model_inbox(std::size_t i) { return router_.inbox(i); }
  std::uint64_t poses_written(std::size_t i) const { return poses_written_[i].load(); }
  std::uint64_t models_for_others() const {
    return router_.models_for_unknown_devices() + router_.models_for_other_sessions();
  }
  // The server device i follows (0: none yet), and the models of any other one it dropped.
  std::uint64_t followed_server(std::size_t i) const { return router_.followed_server(i); }
  std::uint64_t models_from_other_servers(std::size_t i) const { return router_.models_from_other_servers(i); }
  std::uint64_t server_switches(std::size_t i) const { return router_.server_switches(i); }
  const std::string& config_origin() const { return dds_.config_origin(); }
  // Servers whose pose reader matches device i's (0: no server serves its session).
  std::uint32_t matched_servers(std::size_t i) const { return dds_.MatchedServers(i); }

 private:
  void WriteNewestPoses();

  ModelRouter router_;
  std::unique_ptr<common::LatestValue<SensedPose>[]> pose_outboxes_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> poses_written_;
  DeviceDds dds_;  // last: its thread uses the members above, so it stops first
};

}  // namespace hapsim::bridge
