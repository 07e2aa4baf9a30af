#include "hapsim/bridge/model_router.h"

#include <spdlog/spdlog.h>

#include <array>
#include <cstring>

#include "hapsim/common/clock.h"
#include "hapsim/wire/topics_wire.h"

namespace hapsim::bridge {

ModelRouter::ModelRouter(std::uint32_t first_device_id, const std::vector<std::string>& sessions)
    : first_device_id_(first_device_id), n_(sessions.size()), slots_(std::make_unique<Slot[]>(sessions.size())) {
  for (std::size_t i = 0; i < n_; ++i) std::strncpy(slots_[i].session, sessions[i].c_str(), sizeof slots_[i].session - 1);
}

void ModelRouter::Route(const hapsim_dds_LocalForceModel& model, std::int64_t received_ns) {
  // Unsigned wrap-around sends ids below first_device_id_ past n_ too.
  const std::size_t device = static_cast<std::uint32_t>(model.device_id - first_device_id_);
  if (device >= n_) {
    unknown_device_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  Slot& slot = slots_[device];
  if (std::strncmp(model.session, slot.session, sizeof slot.session) != 0) {
    other_session_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (!FollowsServer(slot, model.server_instance, received_ns)) {
    slot.other_server.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  slot.inbox.Publish(ToReceivedModel(model, received_ns));
  slot.routed.fetch_add(1, std::memory_order_relaxed);
}

bool ModelRouter::FollowsServer(Slot& slot, std::uint64_t server_instance, std::int64_t received_ns) {
  const std::uint64_t followed = slot.followed_server.load(std::memory_order_relaxed);
  if (slot.following && server_instance == followed) {
    slot.last_routed_ns = received_ns;
    return true;
  }
  if (slot.following) {
    if (received_ns - slot.last_routed_ns < kServerSilenceBeforeSwitch_ns) {
      if (slot.other_server.load(std::memory_order_relaxed) == 0) {
        spdlog::warn(
            "session '{}': another server (instance {:016x}) also publishes force models; following "
            "server {:016x} and dropping the other's (give each server its own --dds-domain)",
            slot.session, server_instance, followed);
      }
      return false;
    }
    slot.switches.fetch_add(1, std::memory_order_relaxed);
    spdlog::warn("session '{}': server {:016x} silent for {:.1f} s; now following server {:016x}", slot.session,
                 followed, static_cast<double>(received_ns - slot.last_routed_ns) * 1e-9, server_instance);
  }
  slot.following = true;
  slot.followed_server.store(server_instance, std::memory_order_relaxed);
  slot.last_routed_ns = received_ns;
  return true;
}

ReceivedModel ToReceivedModel(const hapsim_dds_LocalForceModel& model, std::int64_t received_ns) {
  ReceivedModel r;
  r.model = wire::UnpackForceModel(model);
  r.seq = model.seq;
  r.echo_pose_seq = model.echo_pose_seq;
  r.server_instance = model.server_instance;
  r.received_ns = received_ns;
  r.echo_pose_held_ns = static_cast<std::int64_t>(model.echo_pose_held_us) * 1000;
  r.next_model_within_s = model.next_model_within_ms * 1e-3;
  return r;
}

std::size_t TakeAndRouteModels(dds::Reader<hapsim_dds_LocalForceModel>& reader, ModelRouter& router) {
  std::array<hapsim_dds_LocalForceModel, 16> batch;
  std::size_t total = 0;
  for (;;) {
    const std::size_t n = reader.Take(batch);
    const std::int64_t now_ns = common::SteadyNowNs();
    for (std::size_t i = 0; i < n; ++i) router.Route(batch[i], now_ns);
    total += n;
    if (n < batch.size()) return total;
  }
}

}  // namespace hapsim::bridge
