#include "hapsim/netlab/forwarder.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

namespace hapsim::netlab {
namespace {

constexpr std::size_t kMaxPacketBytes = 65536;
constexpr int kReadBatch = 256;                   // per device per wake, so one host cannot starve the others
constexpr std::int64_t kMaxWaitNs = 100'000'000;  // wake at least every 100 ms to see *stop

}  // namespace

std::int64_t MonotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

ForwarderResult RunForwarder(LinkSwitch* link_switch, const std::vector<int>& tun_fds, double seconds,
                             const std::atomic<bool>& stop, std::int64_t spin_lead_ns) {
  ForwarderResult result;
  common::SampleWindow lateness_s(1 << 20);
  std::vector<pollfd> polls;
  for (int fd : tun_fds) polls.push_back({fd, POLLIN, 0});
  std::vector<std::uint8_t> buffer(kMaxPacketBytes);
  const std::int64_t start_ns = MonotonicNs();
  const std::int64_t end_ns = start_ns + static_cast<std::int64_t>(seconds * 1e9);
  const LinkSwitch::Deliver write_to_host = [&](std::size_t to, const std::vector<std::uint8_t>& packet,
                                                std::int64_t due_ns) {
    if (polls[to].fd < 0) {
      ++result.to_vanished;
      return;
    }
    if (write(tun_fds[to], packet.data(), packet.size()) < 0) ++result.write_errors;
    lateness_s.Record(static_cast<double>(MonotonicNs() - due_ns) * 1e-9);
  };
  while (!stop.load(std::memory_order_relaxed)) {
    std::int64_t now_ns = MonotonicNs();
    if (now_ns >= end_ns) break;
    // Within spin_lead_ns of the next delivery, poll without sleeping: an idle
    // CPU can be woken 0.1 ms or more late, and that would be the link's error.
    const std::int64_t wait_ns =
        std::clamp(std::min(link_switch->NextDueNs(), end_ns) - now_ns - spin_lead_ns, std::int64_t{0}, kMaxWaitNs);
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000), static_cast<long>(wait_ns % 1'000'000'000)};
    if (ppoll(polls.data(), polls.size(), &timeout, nullptr) < 0 && errno != EINTR) {
      result.ok = false;
      result.error = std::string("ppoll: ") + std::strerror(errno);
      break;
    }
    for (std::size_t host = 0; host < polls.size(); ++host) {
      if (polls[host].fd >= 0 && (polls[host].revents & (POLLERR | POLLHUP | POLLNVAL))) {
        // The device was deleted: poll ignores a negative fd from now on.
        result.vanished_hosts.push_back(link_switch->hosts()[host].name);
        polls[host].fd = -1;
        continue;
      }
      if (!(polls[host].revents & POLLIN)) continue;
      for (int i = 0; i < kReadBatch; ++i) {
        const ssize_t n = read(polls[host].fd, buffer.data(), buffer.size());
        if (n <= 0) break;  // EAGAIN: drained
        link_switch->Send(host, buffer.data(), static_cast<std::size_t>(n), MonotonicNs());
      }
    }
    link_switch->Advance(MonotonicNs(), write_to_host);
  }
  result.elapsed_s = static_cast<double>(MonotonicNs() - start_ns) * 1e-9;
  result.lateness_s = lateness_s.Summary();
  return result;
}

}  // namespace hapsim::netlab
