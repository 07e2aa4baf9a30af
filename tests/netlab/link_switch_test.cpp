// The emulated switch: a packet crosses the sender's link then the
// receiver's, so one-way delays add; multicast reaches every other host,
// each copy through its own link; packets to unknown hosts and non-IPv4
// packets are counted, never forwarded.
#include "hapsim/netlab/link_switch.h"

#include <gtest/gtest.h>

#include "netlab/netlab_test_packets.h"

namespace hapsim::netlab {
namespace {

using test::Host;
using test::Ipv4To;
using test::kNsPerMs;

struct Delivery {
  std::size_t to;
  std::int64_t at_ns;
};

TEST(LinkSwitch, AOneWayDelayIsTheSumOfBothAccessLinks) {
  LinkSwitch sw({Host("server", "10.77.0.1", ""), Host("trainee", "10.77.0.2", "delay_ms=10"),
                 Host("viewer", "10.77.0.3", "delay_ms=25")},
                1, 0);
  std::vector<Delivery> got;
  const auto record = [&](std::size_t to, const std::vector<std::uint8_t>&, std::int64_t due) {
    got.push_back({to, due});
  };
  const auto p = Ipv4To("10.77.0.1");
  sw.Send(1, p.data(), p.size(), 0);  // trainee -> server: 10 + 0 ms
  sw.Send(2, p.data(), p.size(), 0);  // viewer -> server: 25 + 0 ms
  const auto q = Ipv4To("10.77.0.3");
  sw.Send(1, q.data(), q.size(), 0);  // trainee -> viewer: 10 + 25 ms
  EXPECT_EQ(sw.Advance(9 * kNsPerMs, record), 0u);
  EXPECT_EQ(sw.NextDueNs(), 10 * kNsPerMs);
  EXPECT_EQ(sw.Advance(100 * kNsPerMs, record), 3u);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[0].to, 0u);
  EXPECT_EQ(got[0].at_ns, 10 * kNsPerMs);
  EXPECT_EQ(got[1].to, 0u);
  EXPECT_EQ(got[1].at_ns, 25 * kNsPerMs);
  EXPECT_EQ(got[2].to, 2u);
  EXPECT_EQ(got[2].at_ns, 35 * kNsPerMs);
  EXPECT_EQ(sw.counters(0).received_packets, 2u);
  EXPECT_EQ(sw.counters(1).sent_packets, 2u);
  EXPECT_EQ(sw.queued_bytes(), 0u);
}

TEST(LinkSwitch, MulticastReachesEveryOtherHostThroughItsOwnLink) {
  LinkSwitch sw({Host("a", "10.77.0.1", ""), Host("b", "10.77.0.2", "delay_ms=5"), Host("c", "10.77.0.3", "loss=1")}, 1,
                0);
  std::vector<Delivery> got;
  const auto p = Ipv4To("239.255.0.1");  // Cyclone's discovery group
  sw.Send(0, p.data(), p.size(), 0);
  sw.Advance(kNsPerMs * 100, [&](std::size_t to, const std::vector<std::uint8_t>&, std::int64_t due) {
    got.push_back({to, due});
  });
  ASSERT_EQ(got.size(), 1u);  // not back to a, lost on c's link
  EXPECT_EQ(got[0].to, 1u);
  EXPECT_EQ(got[0].at_ns, 5 * kNsPerMs);
  EXPECT_EQ(sw.counters(2).lost, 1u);
  EXPECT_EQ(sw.counters(0).sent_multicast_packets, 1u);  // counted once, at the sender
  const auto unicast = Ipv4To("10.77.0.2");
  sw.Send(0, unicast.data(), unicast.size(), kNsPerMs * 100);
  EXPECT_EQ(sw.counters(0).sent_multicast_packets, 1u);
  EXPECT_EQ(sw.counters(0).sent_packets, 2u);
}

TEST(LinkSwitch, UnknownAddressesAndNonIpv4AreCountedNotForwarded) {
  LinkSwitch sw({Host("a", "10.77.0.1", ""), Host("b", "10.77.0.2", "")}, 1, 0);
  const auto stranger = Ipv4To("10.77.0.9");
  const auto self = Ipv4To("10.77.0.1");
  std::vector<std::uint8_t> ipv6(60, 0);
  ipv6[0] = 0x60;
  const std::uint8_t runt[3] = {0x45, 0, 0};
  sw.Send(0, stranger.data(), stranger.size(), 0);
  sw.Send(0, self.data(), self.size(), 0);
  sw.Send(0, ipv6.data(), ipv6.size(), 0);
  sw.Send(0, runt, sizeof runt, 0);
  int delivered = 0;
  sw.Advance(kNsPerMs, [&](std::size_t, const std::vector<std::uint8_t>&, std::int64_t) { ++delivered; });
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(sw.counters(0).unroutable, 4u);
}

TEST(LinkSwitch, PacketsInFlightAreBoundedInBytes) {
  LinkSwitch sw({Host("a", "10.77.0.1", "delay_ms=100"), Host("b", "10.77.0.2", "")}, 1, 0, 1000);
  const auto p = Ipv4To("10.77.0.2", 400);
  for (int i = 0; i < 4; ++i) sw.Send(0, p.data(), p.size(), i);
  EXPECT_EQ(sw.queued_bytes(), 800u);
  EXPECT_EQ(sw.counters(0).queue, 2u);
}

}  // namespace
}  // namespace hapsim::netlab
