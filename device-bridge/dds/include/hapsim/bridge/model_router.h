// Hands each received force model to the inbox of the device it addresses:
// device i has id first_device_id + i and drives sessions[i]. Each device
// reads models only in its session's DDS partition, so other sessions'
// models never arrive; should one arrive anyway (another device id, or one
// of ours but another session), it is counted and dropped — the bridge
// reports that count, and it must stay 0.
// A device follows one server: it locks to the server instance of the
// first model it routes and drops and counts every other instance's models
// (two servers on one domain may both serve the session id), until the one
// it follows has been silent for kServerSilenceBeforeSwitch_ns (a restart).
// One receive thread routes (the inboxes' single producer) and unpacks
// each model it keeps into core types; the servo thread takes from the
// inboxes (their single consumer).
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hapsim/dds/dds.h"
#include "hapsim/servo/servo_channel.h"
#include "haptics.h"  // the topics' IDL structs

namespace hapsim::bridge {

class ModelRouter {
 public:
  // Long past the watchdog's zero force (100 ms): a switch never mixes two servers' models in one force ramp.
  static constexpr std::int64_t kServerSilenceBeforeSwitch_ns = 1'000'000'000;

  ModelRouter(std::uint32_t first_device_id, const std::vector<std::string>& sessions);

  // Receive thread only. received_ns: arrival time on this process's steady clock.
  void Route(const hapsim_dds_LocalForceModel& model, std::int64_t received_ns);

  std::size_t devices() const { return n_; }
  std::uint32_t first_device_id() const { return first_device_id_; }
  std::string session(std::size_t device) const { return slots_[device].session; }
  common::LatestValue<ReceivedModel>& inbox(std::size_t device) { return slots_[device].inbox; }
  std::uint64_t models_routed(std::size_t device) const { return slots_[device].routed.load(std::memory_order_relaxed); }
  std::uint64_t models_for_unknown_devices() const { return unknown_device_.load(std::memory_order_relaxed); }
  std::uint64_t models_for_other_sessions() const { return other_session_.load(std::memory_order_relaxed); }
  // The server instance device follows (0 before its first model).
  std::uint64_t followed_server(std::size_t device) const {
    return slots_[device].followed_server.load(std::memory_order_relaxed);
  }
  std::uint64_t models_from_other_servers(std::size_t device) const {
    return slots_[device].other_server.load(std::memory_order_relaxed);
  }
  std::uint64_t server_switches(std::size_t device) const {
    return slots_[device].switches.load(std::memory_order_relaxed);
  }

 private:
  // One cache line apart, so the receive thread's writes to one device's
  // counter do not slow the servo thread's reads of a neighbour's inbox.
  struct alignas(64) Slot {
    common::LatestValue<ReceivedModel> inbox;
    std::atomic<std::uint64_t> routed{0};
    std::atomic<std::uint64_t> followed_server{0}, other_server{0}, switches{0};
    bool following = false;           // receive thread only
    std::int64_t last_routed_ns = 0;  // receive thread only
    char session[sizeof(hapsim_dds_LocalForceModel::session)] = {};
  };
  // Whether slot takes a model of server_instance that arrived at received_ns.
  bool FollowsServer(Slot& slot, std::uint64_t server_instance, std::int64_t received_ns);

  std::uint32_t first_device_id_;
  std::size_t n_;
  std::unique_ptr<Slot[]> slots_;
  std::atomic<std::uint64_t> unknown_device_{0}, other_session_{0};
};

// A model off the wire as the servo reads it (hapsim::wire unpacks and checks it).
ReceivedModel ToReceivedModel(const hapsim_dds_LocalForceModel& model, std::int64_t received_ns);

// Takes every force model waiting in reader, stamps the batch with one
// arrival time and routes it. Returns how many were taken.
std::size_t TakeAndRouteModels(dds::Reader<hapsim_dds_LocalForceModel>& reader, ModelRouter& router);

}  // namespace hapsim::bridge
