// Hands each received force model to the inbox of the device it addresses:
// device i has id first_device_id + i and drives sessions[i]. Each device
// reads models only in its session's DDS partition, so other sessions'
// models never arrive; should one arrive anyway (another device id, or one
// of ours but another session), it is counted and dropped — the bridge
// reports that count, and it must stay 0.
// One receive thread routes (the inboxes' single producer); the servo
// thread takes from the inboxes (their single consumer).
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hapsim/bridge/servo_channel.h"
#include "hapsim/dds/dds.h"

namespace hapsim::bridge {

class ModelRouter {
 public:
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

 private:
  // One cache line apart, so the receive thread's writes to one device's
  // counter do not slow the servo thread's reads of a neighbour's inbox.
  struct alignas(64) Slot {
    common::LatestValue<ReceivedModel> inbox;
    std::atomic<std::uint64_t> routed{0};
    char session[sizeof(hapsim_dds_LocalForceModel::session)] = {};
  };

  std::uint32_t first_device_id_;
  std::size_t n_;
  std::unique_ptr<Slot[]> slots_;
  std::atomic<std::uint64_t> unknown_device_{0}, other_session_{0};
};

// Takes every force model waiting in reader, stamps the batch with one
// arrival time and routes it. Returns how many were taken.
std::size_t TakeAndRouteModels(dds::Reader<hapsim_dds_LocalForceModel>& reader, ModelRouter& router);

}  // namespace hapsim::bridge
