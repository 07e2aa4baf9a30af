// The forwarder's loop, with datagram socket pairs standing in for the TUN
// devices (one packet per read and write, as a TUN device gives): a packet
// reaches its host through the emulated link no earlier than its delay,
// whether the loop sleeps until it is due or spins through the last stretch.
#include "hapsim/netlab/forwarder.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <thread>

#include "netlab/netlab_test_packets.h"

namespace hapsim::netlab {
namespace {

using test::Host;
using test::Ipv4To;
using test::kNsPerMs;

// The "device" end the forwarder holds and the "host" end the test uses.
struct FakeTun {
  int forwarder_fd = -1, host_fd = -1;
  FakeTun() {
    std::array<int, 2> fds{};
    EXPECT_EQ(socketpair(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK, 0, fds.data()), 0);
    forwarder_fd = fds[0], host_fd = fds[1];
  }
  ~FakeTun() {
    close(forwarder_fd);
    close(host_fd);
  }
};

class ForwarderDelivers : public ::testing::TestWithParam<std::int64_t> {};

TEST_P(ForwarderDelivers, APacketArrivesNoEarlierThanItsLinksDelay) {
  const std::int64_t spin_lead_ns = GetParam();
  constexpr std::int64_t kDelayNs = 5 * kNsPerMs;
  const std::vector<HostSpec> hosts = {Host("server", "10.77.0.1", ""), Host("trainee", "10.77.0.2", "delay_ms=5")};
  FakeTun server, trainee;
  LinkSwitch link_switch(hosts, 1, MonotonicNs());
  std::atomic<bool> stop{false};
  ForwarderResult result;
  std::thread forwarder([&] {
    result = RunForwarder(&link_switch, {server.forwarder_fd, trainee.forwarder_fd}, 5.0, stop, spin_lead_ns);
  });
  constexpr int kPackets = 5;
  for (int i = 0; i < kPackets; ++i) {
    const auto packet = Ipv4To("10.77.0.1");
    const std::int64_t sent_ns = MonotonicNs();
    ASSERT_EQ(write(trainee.host_fd, packet.data(), packet.size()), static_cast<ssize_t>(packet.size()));
    pollfd arrival{server.host_fd, POLLIN, 0};
    ASSERT_EQ(poll(&arrival, 1, 2000), 1) << "packet " << i << " never reached the server";
    const std::int64_t arrived_ns = MonotonicNs();
    std::array<std::uint8_t, 128> got{};
    ASSERT_EQ(read(server.host_fd, got.data(), got.size()), static_cast<ssize_t>(packet.size()));
    EXPECT_GE(arrived_ns - sent_ns, kDelayNs) << "packet " << i << " came early";
  }
  stop = true;
  forwarder.join();
  EXPECT_TRUE(result.ok) << result.error;
  EXPECT_EQ(result.write_errors, 0u);
  EXPECT_EQ(result.lateness_s.count, static_cast<std::size_t>(kPackets));
  EXPECT_GE(result.lateness_s.min, 0.0) << "the forwarder wrote a packet before it was due";
}

INSTANTIATE_TEST_SUITE_P(SleepingOrSpinning, ForwarderDelivers, ::testing::Values(0, 1 * kNsPerMs),
                         [](const ::testing::TestParamInfo<std::int64_t>& param_info) {
                           return param_info.param == 0 ? "Sleeping" : "SpinningTheLastMs";
                         });

}  // namespace
}  // namespace hapsim::netlab
