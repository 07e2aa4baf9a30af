// The link model's statistics against their definitions: a fixed delay is
// exact, jitter stays within its band with the uniform law's mean and
// spread, loss rates and burst lengths match the Gilbert-Elliott chain's
// stationary values within binomial tolerances, a bandwidth cap spaces
// packets by their serialisation time, outages drop exactly their window.
#include "hapsim/netlab/link_model.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hapsim::netlab {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kStart = 5'000 * kMs;  // an arbitrary clock origin

LinkProfile Parse(const std::string& text) {
  LinkProfile p;
  std::string error;
  EXPECT_TRUE(ParseLinkProfile(text, &p, &error)) << error;
  return p;
}

TEST(LinkModel, AFixedDelayIsExactToTheNanosecond) {
  LinkModel link(Parse("delay_ms=12.5"), 1, kStart);
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t now = kStart + i * 997'000;
    const Admission a = link.Offer(now, 200);
    ASSERT_EQ(a.fate, Fate::kDelivered);
    EXPECT_EQ(a.leave_ns - now, 12'500'000);
  }
}

TEST(LinkModel, JitterIsUniformWithinItsBandWhenReorderingIsAllowed) {
  LinkModel link(Parse("delay_ms=10,jitter_ms=5,reorder=1"), 7, kStart);
  const int n = 100'000;
  double sum = 0.0, sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const std::int64_t now = kStart + i * kMs;
    const double d_ms = static_cast<double>(link.Offer(now, 100).leave_ns - now) / kMs;
    ASSERT_GE(d_ms, 5.0 - 1e-6);
    ASSERT_LE(d_ms, 15.0 + 1e-6);
    sum += d_ms;
    sum_sq += d_ms * d_ms;
  }
  const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
  const double sd_uniform = 5.0 / std::sqrt(3.0);  // U(-5, 5) ms
  // Mean within 5 standard errors; the spread within 2 % of the law's.
  EXPECT_NEAR(mean, 10.0, 5.0 * sd_uniform / std::sqrt(n));
  EXPECT_NEAR(sd, sd_uniform, 0.02 * sd_uniform);
}

TEST(LinkModel, WithoutReorderingAPacketNeverOvertakesTheOneBefore) {
  LinkModel link(Parse("delay_ms=10,jitter_ms=5"), 3, kStart);
  std::int64_t previous = 0;
  int held_back = 0;
  for (int i = 0; i < 10'000; ++i) {
    const std::int64_t now = kStart + i * kMs;
    const std::int64_t leave = link.Offer(now, 100).leave_ns;
    ASSERT_GE(leave, previous);
    ASSERT_LE(leave - now, 15 * kMs);
    if (leave - now < 5 * kMs) ++held_back;  // impossible: held only later, never earlier
    previous = leave;
  }
  EXPECT_EQ(held_back, 0);
}

TEST(LinkModel, RandomLossMatchesItsProbability) {
  for (double p : {0.01, 0.1}) {
    LinkModel link(Parse("loss=" + std::to_string(p)), 11, kStart);
    const int n = 200'000;
    int lost = 0;
    for (int i = 0; i < n; ++i) lost += link.Offer(kStart + i * kMs, 100).fate == Fate::kLost;
    // Binomial: within 5 standard deviations.
    EXPECT_NEAR(static_cast<double>(lost) / n, p, 5.0 * std::sqrt(p * (1 - p) / n)) << "p = " << p;
  }
}

TEST(LinkModel, LossBurstsHaveTheirMeanLengthAndStationaryShare) {
  // Enter a burst with probability r per packet, leave with 1/L: bursts are
  // geometric with mean L, and the chain spends r L / (1 + r L) in bursts.
  const double r = 0.001, L = 150.0;
  LinkModel link(Parse("burst_rate=0.001,burst_packets=150"), 5, kStart);
  const int n = 2'000'000;
  int dropped = 0, bursts = 0;
  bool was_burst = false;
  for (int i = 0; i < n; ++i) {
    const bool burst = link.Offer(kStart + i * kMs, 100).fate == Fate::kBurst;
    dropped += burst;
    bursts += burst && !was_burst;
    was_burst = burst;
  }
  const double mean_length = static_cast<double>(dropped) / bursts;
  // ~1700 bursts: the mean length's standard error is ~L/sqrt(1700) = 2.4 %.
  EXPECT_NEAR(mean_length, L, 0.12 * L) << bursts << " bursts";
  const double share = r * L / (1.0 + r * L);
  EXPECT_NEAR(static_cast<double>(dropped) / n, share, 0.12 * share);
}

TEST(LinkModel, ABandwidthCapSpacesPacketsByTheirSerialisationTime) {
  // 1 Mbit/s: a 1250-byte packet takes exactly 10 ms on the wire.
  LinkModel link(Parse("rate_mbit_s=1,queue_ms=35,delay_ms=2"), 1, kStart);
  std::vector<Admission> burst;
  for (int i = 0; i < 6; ++i) burst.push_back(link.Offer(kStart, 1250));
  // Waits of 0, 10, 20, 30 ms fit the 35 ms queue; 40 and 50 do not.
  for (int i = 0; i < 4; ++i) {
    ASSERT_EQ(burst[i].fate, Fate::kDelivered) << i;
    EXPECT_EQ(burst[i].leave_ns - kStart, (i + 1) * 10 * kMs + 2 * kMs) << i;
  }
  EXPECT_EQ(burst[4].fate, Fate::kQueue);
  EXPECT_EQ(burst[5].fate, Fate::kQueue);
}

TEST(LinkModel, AnOutageDropsExactlyItsWindow) {
  LinkModel link(Parse("outage=1+2"), 1, kStart);
  EXPECT_EQ(link.Offer(kStart + 999 * kMs, 100).fate, Fate::kDelivered);
  EXPECT_EQ(link.Offer(kStart + 1000 * kMs, 100).fate, Fate::kOutage);
  EXPECT_EQ(link.Offer(kStart + 2999 * kMs, 100).fate, Fate::kOutage);
  EXPECT_EQ(link.Offer(kStart + 3000 * kMs, 100).fate, Fate::kDelivered);
}

TEST(LinkProfileText, BadSettingsAreNamed) {
  LinkProfile p;
  std::string error;
  EXPECT_FALSE(ParseLinkProfile("delay=10", &p, &error));
  EXPECT_NE(error.find("unknown link key 'delay'"), std::string::npos) << error;
  EXPECT_FALSE(ParseLinkProfile("loss=1.5", &p, &error));
  EXPECT_NE(error.find("loss must be within [0, 1]"), std::string::npos) << error;
  EXPECT_FALSE(ParseLinkProfile("jitter_ms=nan", &p, &error));
  EXPECT_NE(error.find("jitter_ms needs a number"), std::string::npos) << error;
  EXPECT_FALSE(ParseLinkProfile("outage=3", &p, &error));
  EXPECT_NE(error.find("START_S+DURATION_S"), std::string::npos) << error;
  EXPECT_FALSE(ParseLinkProfile("burst_rate=0.01", &p, &error));
  EXPECT_NE(error.find("burst_packets"), std::string::npos) << error;
  EXPECT_FALSE(ParseLinkProfile("delay_ms", &p, &error));
  EXPECT_NE(error.find("not KEY=VALUE"), std::string::npos) << error;
}

TEST(LinkProfileText, ItsTextReadsBackToTheSameProfile) {
  const LinkProfile p = Parse(
      "delay_ms=25,jitter_ms=5,reorder=1,loss=0.01,burst_rate=0.002,burst_packets=20,"
      "rate_mbit_s=100,queue_ms=40,outage=3+2,outage=8+0.5");
  const LinkProfile q = Parse(ToString(p));
  EXPECT_EQ(ToString(q), ToString(p));
  ASSERT_EQ(q.outages.size(), 2u);
  EXPECT_EQ(q.outages[1].start_s, 8.0);
  EXPECT_TRUE(q.reorder);
}

}  // namespace
}  // namespace hapsim::netlab
