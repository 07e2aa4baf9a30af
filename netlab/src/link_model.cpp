#include "hapsim/netlab/link_model.h"

#include <algorithm>
#include <cmath>

namespace hapsim::netlab {

const char* ToString(Fate fate) {
  switch (fate) {
    case Fate::kDelivered:
      return "delivered";
    case Fate::kLost:
      return "lost";
    case Fate::kBurst:
      return "burst";
    case Fate::kQueue:
      return "queue";
    case Fate::kOutage:
      return "outage";
  }
  return "?";
}

LinkModel::LinkModel(const LinkProfile& profile, std::uint64_t seed, std::int64_t start_ns)
    : profile_(profile), random_(seed), start_ns_(start_ns), wire_free_ns_(start_ns), last_leave_ns_(start_ns) {}

bool LinkModel::InOutage(std::int64_t now_ns) const {
  const double t_s = static_cast<double>(now_ns - start_ns_) * 1e-9;
  return std::any_of(profile_.outages.begin(), profile_.outages.end(),
                     [t_s](const Outage& o) { return t_s >= o.start_s && t_s < o.start_s + o.duration_s; });
}

Admission LinkModel::Offer(std::int64_t now_ns, std::size_t bytes) {
  if (InOutage(now_ns)) return {Fate::kOutage, 0};
  // Loss: the burst state advances once per packet (Gilbert-Elliott).
  if (in_burst_) {
    if (unit_(random_) < 1.0 / profile_.burst_packets) in_burst_ = false;
  } else if (profile_.burst_rate > 0.0 && unit_(random_) < profile_.burst_rate) {
    in_burst_ = true;
  }
  if (in_burst_) return {Fate::kBurst, 0};
  if (profile_.loss > 0.0 && unit_(random_) < profile_.loss) return {Fate::kLost, 0};
  // Bandwidth: the packet waits for the wire, then takes bytes*8/rate on it.
  std::int64_t on_wire_ns = now_ns;
  if (profile_.rate_mbit_s > 0.0) {
    const std::int64_t start_ns = std::max(now_ns, wire_free_ns_);
    if (static_cast<double>(start_ns - now_ns) > profile_.queue_ms * 1e6) return {Fate::kQueue, 0};
    const double serialise_ns = static_cast<double>(bytes) * 8.0 / (profile_.rate_mbit_s * 1e6) * 1e9;
    wire_free_ns_ = start_ns + static_cast<std::int64_t>(std::llround(serialise_ns));
    on_wire_ns = wire_free_ns_;
  }
  // Propagation, with jitter uniform in ±jitter_ms.
  double delay_ms = profile_.delay_ms;
  if (profile_.jitter_ms > 0.0) delay_ms += profile_.jitter_ms * (2.0 * unit_(random_) - 1.0);
  std::int64_t leave_ns = on_wire_ns + static_cast<std::int64_t>(std::llround(std::max(0.0, delay_ms) * 1e6));
  if (!profile_.reorder) leave_ns = std::max(leave_ns, last_leave_ns_);
  last_leave_ns_ = leave_ns;
  return {Fate::kDelivered, leave_ns};
}

}  // namespace hapsim::netlab
