#include "hapsim/bridge/model_router.h"

#include <array>
#include <cstring>

#include "hapsim/common/clock.h"

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
  slot.inbox.Publish(ReceivedModel{model, received_ns});
  slot.routed.fetch_add(1, std::memory_order_relaxed);
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
