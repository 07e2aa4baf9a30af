// The link emulator's process loop: packets read from each host's TUN
// device go through the LinkSwitch and are written to the destination's TUN
// device when due. One thread, ppoll with nanosecond timeouts (or, just
// before a packet is due, a ppoll that does not wait).
#pragma once
#include <atomic>
#include <string>
#include <vector>

#include "hapsim/common/stats.h"
#include "hapsim/netlab/link_switch.h"

namespace hapsim::netlab {

struct ForwarderResult {
  bool ok = true;
  std::string error;  // when !ok: the I/O call that failed
  double elapsed_s = 0.0;
  std::uint64_t write_errors = 0;  // a TUN write that failed
  // Hosts whose TUN device went away (deleted: a pulled cable); the others
  // are still served, and packets for a vanished host are dropped and counted.
  std::vector<std::string> vanished_hosts;
  std::uint64_t to_vanished = 0;
  common::Percentiles lateness_s;  // written minus due, per delivered packet
};

// tun_fds[i] is host i's device. Runs until *stop, or for `seconds`.
// spin_lead_ns > 0: sleep only until that long before the next packet is
// due, then poll the devices without sleeping until it is (punctual
// deliveries for the CPU time of the spin).
ForwarderResult RunForwarder(LinkSwitch* link_switch, const std::vector<int>& tun_fds, double seconds,
                             const std::atomic<bool>& stop, std::int64_t spin_lead_ns = 0);

// This process's monotonic clock [ns] (the LinkSwitch's clock here).
std::int64_t MonotonicNs();

}  // namespace hapsim::netlab
