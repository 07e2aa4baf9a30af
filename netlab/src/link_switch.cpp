#include "hapsim/netlab/link_switch.h"

#include <limits>

#include "hapsim/netlab/ip_packet.h"

namespace hapsim::netlab {

LinkSwitch::LinkSwitch(std::vector<HostSpec> hosts, std::uint64_t seed, std::int64_t start_ns,
                       std::size_t max_queued_bytes)
    : hosts_(std::move(hosts)), counters_(hosts_.size()), max_queued_bytes_(max_queued_bytes) {
  for (std::size_t i = 0; i < hosts_.size(); ++i) {
    // Every link draws from its own seeded stream: one host's traffic does
    // not change another link's losses.
    uplinks_.emplace_back(hosts_[i].link, seed + 2 * i, start_ns);
    downlinks_.emplace_back(hosts_[i].link, seed + 2 * i + 1, start_ns);
  }
}

std::size_t LinkSwitch::HostOf(std::uint32_t address) const {
  for (std::size_t i = 0; i < hosts_.size(); ++i) {
    if (hosts_[i].address == address) return i;
  }
  return hosts_.size();
}

void LinkSwitch::Count(std::size_t host, Fate fate) {
  HostCounters& c = counters_[host];
  switch (fate) {
    case Fate::kLost:
      ++c.lost;
      break;
    case Fate::kBurst:
      ++c.burst;
      break;
    case Fate::kQueue:
      ++c.queue;
      break;
    case Fate::kOutage:
      ++c.outage;
      break;
    case Fate::kDelivered:
      break;
  }
}

void LinkSwitch::Send(std::size_t from, const std::uint8_t* data, std::size_t bytes, std::int64_t now_ns) {
  HostCounters& c = counters_[from];
  ++c.sent_packets;
  c.sent_bytes += bytes;
  const PacketRoute route = RouteOf(data, bytes);
  std::size_t to = kEveryone;
  if (!route.ipv4) {
    ++c.unroutable;
    return;
  }
  if (route.to_all) ++c.sent_multicast_packets;
  if (!route.to_all) {
    to = HostOf(route.destination);
    if (to == hosts_.size() || to == from) {
      ++c.unroutable;
      return;
    }
  }
  if (queued_bytes_ + bytes > max_queued_bytes_) {
    ++c.queue;
    return;
  }
  const Admission up = uplinks_[from].Offer(now_ns, bytes);
  if (up.fate != Fate::kDelivered) {
    Count(from, up.fate);
    return;
  }
  queued_bytes_ += bytes;
  in_flight_.push({up.leave_ns, next_order_++, true, from, to,
                   std::make_shared<const std::vector<std::uint8_t>>(data, data + bytes)});
}

void LinkSwitch::OntoDownlink(const InFlight& arrived, std::size_t to) {
  const std::size_t bytes = arrived.packet->size();
  const Admission down = downlinks_[to].Offer(arrived.due_ns, bytes);
  if (down.fate != Fate::kDelivered) {
    Count(to, down.fate);
    return;
  }
  queued_bytes_ += bytes;
  in_flight_.push({down.leave_ns, next_order_++, false, arrived.from, to, arrived.packet});
}

std::size_t LinkSwitch::Advance(std::int64_t now_ns, const Deliver& deliver) {
  std::size_t delivered = 0;
  while (!in_flight_.empty() && in_flight_.top().due_ns <= now_ns) {
    const InFlight item = in_flight_.top();
    in_flight_.pop();
    queued_bytes_ -= item.packet->size();
    if (item.on_uplink) {
      if (item.to != kEveryone) {
        OntoDownlink(item, item.to);
      } else {
        for (std::size_t to = 0; to < hosts_.size(); ++to) {
          if (to != item.from) OntoDownlink(item, to);
        }
      }
      continue;
    }
    HostCounters& c = counters_[item.to];
    ++c.received_packets;
    c.received_bytes += item.packet->size();
    deliver(item.to, *item.packet, item.due_ns);
    ++delivered;
  }
  return delivered;
}

std::int64_t LinkSwitch::NextDueNs() const {
  return in_flight_.empty() ? std::numeric_limits<std::int64_t>::max() : in_flight_.top().due_ns;
}

}  // namespace hapsim::netlab
