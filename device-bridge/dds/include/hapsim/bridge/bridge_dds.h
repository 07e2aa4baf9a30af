// The bridge's DDS adapter: a DeviceDds for one device whose I/O thread
// writes the poses the servo loop posts and takes the force models
// addressed to this device and session, stamping their arrival with the
// bridge's clock (Cyclone's lifespan QoS counts from local receive time, so
// age is measured here).
#pragma once
#include <atomic>
#include <string>

#include "hapsim/bridge/device_dds.h"
#include "hapsim/bridge/model_router.h"

namespace hapsim::bridge {

class BridgeDds {
 public:
  BridgeDds(const dds::Options& options, std::uint32_t device_id, std::string session);
  void Start() { dds_.Start(); }
  void Stop() { dds_.Stop(); }
  void Wake() { dds_.Wake(); }

  common::LatestValue<SensedPose>& pose_outbox() { return pose_outbox_; }
  common::LatestValue<ReceivedModel>& model_inbox() { return router_.inbox(0); }
  std::uint64_t poses_written() const { return poses_written_.load(); }
  std::uint64_t models_for_others() const {
    return router_.models_for_unknown_devices() + router_.models_for_other_sessions();
  }
  // The server this bridge follows (0: none yet), and the models of any other one it dropped.
  std::uint64_t followed_server() const { return router_.followed_server(0); }
  std::uint64_t models_from_other_servers() const { return router_.models_from_other_servers(0); }
  std::uint64_t server_switches() const { return router_.server_switches(0); }
  const std::string& config_origin() const { return dds_.config_origin(); }
  // Servers whose pose reader matches ours (0: no server serves the session).
  std::uint32_t matched_servers() const { return dds_.MatchedServers(0); }

 private:
  void WriteNewestPose();

  ModelRouter router_;  // one device: this bridge's
  common::LatestValue<SensedPose> pose_outbox_;
  std::atomic<std::uint64_t> poses_written_{0};
  DeviceDds dds_;  // last: its thread uses the members above, so it stops first
};

}  // namespace hapsim::bridge
