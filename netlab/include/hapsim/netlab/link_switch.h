// The emulated network: hosts, each on its own access link (a LinkModel per
// direction) to one switch. A packet from host A to host B crosses A's
// uplink, then B's downlink; multicast and broadcast go to every other host,
// each copy through its own downlink. Clock and packets come from the
// caller (the TUN forwarder, or a test), so the routing is tested alone.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <string>
#include <vector>

#include "hapsim/netlab/link_model.h"

namespace hapsim::netlab {

struct HostSpec {
  std::string name;
  std::uint32_t address = 0;  // IPv4, host byte order
  LinkProfile link;
};

// What happened to the packets a host sent (up) and was sent (down).
struct HostCounters {
  std::uint64_t sent_packets = 0, sent_bytes = 0;            // offered by the host
  std::uint64_t sent_multicast_packets = 0;                  // ... of them to a multicast or broadcast address
  std::uint64_t received_packets = 0, received_bytes = 0;    // handed to the host
  std::uint64_t lost = 0, burst = 0, queue = 0, outage = 0;  // dropped on its link, either direction
  std::uint64_t unroutable = 0;                              // to an address no host has, or not IPv4
};

class LinkSwitch {
 public:
  // Delivers a packet to host `to` (index into the hosts), due at due_ns.
  using Deliver = std::function<void(std::size_t to, const std::vector<std::uint8_t>& packet, std::int64_t due_ns)>;

  // max_queued_bytes bounds the packets in flight (beyond it: counted as queue drops).
  LinkSwitch(std::vector<HostSpec> hosts, std::uint64_t seed, std::int64_t start_ns,
             std::size_t max_queued_bytes = 256u << 20);

  // Host `from` sent a packet at now_ns (calls in non-decreasing now_ns).
  void Send(std::size_t from, const std::uint8_t* data, std::size_t bytes, std::int64_t now_ns);

  // Moves every packet due by now_ns on: off an uplink into the downlinks,
  // off a downlink to `deliver`. Returns how many were delivered.
  std::size_t Advance(std::int64_t now_ns, const Deliver& deliver);

  // When the next packet is due (INT64_MAX: none in flight).
  std::int64_t NextDueNs() const;

  const std::vector<HostSpec>& hosts() const { return hosts_; }
  const HostCounters& counters(std::size_t host) const { return counters_[host]; }
  std::size_t queued_bytes() const { return queued_bytes_; }

 private:
  struct InFlight {
    std::int64_t due_ns;
    std::uint64_t order;   // ties leave in the order they came
    bool on_uplink;        // true: due to reach the switch; false: due at the host
    std::size_t from, to;  // to: a host, or kEveryone from the uplink
    std::shared_ptr<const std::vector<std::uint8_t>> packet;
    bool operator>(const InFlight& other) const {
      return due_ns != other.due_ns ? due_ns > other.due_ns : order > other.order;
    }
  };
  static constexpr std::size_t kEveryone = static_cast<std::size_t>(-1);

  void Count(std::size_t host, Fate fate);
  void OntoDownlink(const InFlight& arrived, std::size_t to);
  std::size_t HostOf(std::uint32_t address) const;  // hosts_.size(): none

  std::vector<HostSpec> hosts_;
  std::vector<LinkModel> uplinks_, downlinks_;
  std::vector<HostCounters> counters_;
  std::priority_queue<InFlight, std::vector<InFlight>, std::greater<>> in_flight_;
  std::uint64_t next_order_ = 0;
  std::size_t queued_bytes_ = 0, max_queued_bytes_;
};

}  // namespace hapsim::netlab
