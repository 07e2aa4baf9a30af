#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "backends/replay_device.h"
#include "backends/synthetic_device.h"
#include "hapsim/servo/servo_loop.h"

namespace hapsim::bridge {
namespace {

TEST(SyntheticInsertion, FollowsApproachPressHoldWithdrawAtTheScriptedSpeed) {
  SyntheticScript s;  // 10 mm above, 5 mm deep, 10 mm/s, hold 0.5 s
  SyntheticDevice d(s);
  auto at = [&](double t) { return d.Read(t); };
  EXPECT_NEAR(at(0.0).tip_W_m.z(), 0.010, 1e-12);
  EXPECT_STREQ(at(0.5).phase, "approach");
  EXPECT_NEAR(at(0.5).tip_W_m.z(), 0.005, 1e-12);
  EXPECT_STREQ(at(1.25).phase, "press");  // surface at 1.0 s, depth at 1.5 s
  EXPECT_NEAR(at(1.25).tip_W_m.z(), -0.0025, 1e-12);
  EXPECT_NEAR(at(1.25).velocity_W_m_per_s.z(), -0.01, 1e-12);
  EXPECT_STREQ(at(1.7).phase, "hold");
  EXPECT_NEAR(at(1.7).tip_W_m.z(), -0.005, 1e-12);
  EXPECT_STREQ(at(2.5).phase, "withdraw");  // withdraw starts at 2.0 s
  EXPECT_NEAR(at(2.5).tip_W_m.z(), 0.0, 1e-12);
  EXPECT_NEAR(at(3.5).tip_W_m.z(), 0.010, 1e-12);  // cycle of 3.5 s restarts
  EXPECT_FALSE(at(100.0).finished);               // insertion repeats
}

// The cut stroke: approach, press, draw along a straight line or an arc
// (positions against the circle's closed form, velocity against a finite
// difference), blade leaning back against the stroke, lift, done.
TEST(SyntheticCut, DrawsTheIncisionAlongItsPathWithTheBladeLeaningBack) {
  SyntheticScript s;
  s.kind = "cut";
  s.start_height_m = 0.005;
  s.depth_m = 0.0015;
  s.speed_m_per_s = 0.01;
  s.cut_length_m = 0.02;
  s.entry_W_m = Eigen::Vector3d(-0.01, 0.002, 0.0);
  SyntheticDevice straight(s);
  EXPECT_STREQ(straight.Read(0.2).phase, "approach");
  EXPECT_STREQ(straight.Read(0.6).phase, "press");  // surface at 0.5 s, depth at 0.65 s
  const DeviceReading mid = straight.Read(0.65 + 1.0);
  EXPECT_STREQ(mid.phase, "cut");
  EXPECT_LT((mid.tip_W_m - Eigen::Vector3d(0.0, 0.002, -0.0015)).norm(), 1e-12);
  EXPECT_LT((mid.velocity_W_m_per_s - Eigen::Vector3d(0.01, 0, 0)).norm(), 1e-12);
  const Eigen::Vector3d up = mid.orientation_W * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::acos(up.z()), s.blade_tilt_rad, 1e-9);
  EXPECT_LT(up.x(), 0.0);  // leaning back against +x
  EXPECT_STREQ(straight.Read(2.65 + 0.1).phase, "lift");
  EXPECT_TRUE(straight.Read(10.0).finished);
  EXPECT_LT((straight.Read(10.0).tip_W_m - Eigen::Vector3d(0.01, 0.002, 0.005)).norm(), 1e-12);

  s.cut_bend_rad = 3.14159265358979323846 / 2;  // a quarter circle of radius 20 mm / (pi/2)
  SyntheticDevice arc(s);
  const double radius = s.cut_length_m / s.cut_bend_rad;
  const DeviceReading end = arc.Read(0.65 + 2.0 - 1e-9);
  EXPECT_LT((end.tip_W_m.head<2>() - (s.entry_W_m.head<2>() + Eigen::Vector2d(radius, radius))).norm(), 1e-9);
  const DeviceReading a = arc.Read(1.2), b = arc.Read(1.2 + 1e-6);
  EXPECT_LT(((b.tip_W_m - a.tip_W_m) / 1e-6 - a.velocity_W_m_per_s).norm(), 1e-6);
  s.cut_length_m = 0.0;
  EXPECT_THROW(SyntheticDevice{s}, std::invalid_argument);
}

TEST(SyntheticConstantSpeed, RunsOnceInAndOutThenFinishes) {
  SyntheticScript s;
  s.kind = "constant_speed";
  s.depth_m = 0.02;
  s.start_height_m = 0.002;
  s.speed_m_per_s = 0.005;
  SyntheticDevice d(s);
  EXPECT_NEAR(d.Read(2.4).tip_W_m.z(), -0.010, 1e-12);  // 0.4 s approach + 2 s press
  EXPECT_STREQ(d.Read(4.5).phase, "withdraw");         // depth reached at 4.4 s
  EXPECT_TRUE(d.Read(10.0).finished);                  // 4.4 + 4.4 s
}

TEST(SyntheticRandomWalk, StaysInItsBoxAndIsDeterministicPerSeed) {
  SyntheticScript s;
  s.kind = "random_walk";
  s.walk_step_m = 0.002;
  SyntheticDevice a(s), b(s);
  for (int i = 1; i <= 5000; ++i) {
    const auto ra = a.Read(i * 1e-3);
    const auto rb = b.Read(i * 1e-3);
    ASSERT_EQ(ra.tip_W_m, rb.tip_W_m);
    ASSERT_LE(std::abs(ra.tip_W_m.x()), s.walk_radius_m + 1e-12);
    ASSERT_LE(ra.tip_W_m.z(), s.start_height_m + 1e-12);
    ASSERT_GE(ra.tip_W_m.z(), -s.depth_m - 1e-12);
  }
}

// Each axis steps N(0, 30 um) per 1 ms tick, so the speed follows Maxwell's
// distribution with sigma = 0.03 m/s: mean 2 sigma sqrt(2/pi) = 47.9 mm/s
// (5000 ticks: within 3 %, about 10 standard errors), and never near the
// safety chain's 0.6 m/s velocity limit (20 sigma).
TEST(SyntheticRandomWalk, MovesAtAPalpatingHandsSpeed) {
  SyntheticScript s;
  s.kind = "random_walk";
  SyntheticDevice d(s);
  double sum = 0.0, fastest = 0.0;
  for (int i = 1; i <= 5000; ++i) {
    const double speed = d.Read(i * 1e-3).velocity_W_m_per_s.norm();
    sum += speed;
    fastest = std::max(fastest, speed);
  }
  const double maxwell_mean = 2.0 * 0.03 * std::sqrt(2.0 / M_PI);
  EXPECT_NEAR(sum / 5000, maxwell_mean, 0.03 * maxwell_mean);
  EXPECT_LT(fastest, 0.6);
}

TEST(SyntheticDevice, RejectsUnknownScriptAndBadNumbers) {
  SyntheticScript s;
  s.kind = "dance";
  EXPECT_THROW(SyntheticDevice{s}, std::invalid_argument);
  s = {};
  s.speed_m_per_s = 0.0;
  EXPECT_THROW(SyntheticDevice{s}, std::invalid_argument);
}

TEST(ReplayDevice, InterpolatesBetweenRowsAndHoldsAtTheEnd) {
  const auto rows = ParsePoseLog(
      "t_s,x_m,y_m,z_m,qw,qx,qy,qz,extra\n"
      "1.0,0,0,0.01,1,0,0,0,ignored\n"
      "1.1,0,0,0.00,1,0,0,0,ignored\n"
      "1.3,0.002,0,0.00,1,0,0,0\n");
  ReplayDevice d(rows);
  EXPECT_NEAR(d.Read(0.05).tip_W_m.z(), 0.005, 1e-12);  // halfway between the first two rows
  EXPECT_NEAR(d.Read(0.05).velocity_W_m_per_s.z(), -0.1, 1e-12);
  EXPECT_NEAR(d.Read(0.2).tip_W_m.x(), 0.001, 1e-12);
  const auto end = d.Read(1.0);
  EXPECT_TRUE(end.finished);
  EXPECT_NEAR(end.tip_W_m.x(), 0.002, 1e-12);
}

// `hapsim-bridge --trace` says its trace replays: after a late tick the
// servo's catch-up wakes come microseconds apart, and the trace must still
// load (it wrote 6 decimals and repeated times) and replay those poses.
TEST(ReplayDevice, ATraceWithCatchUpTicksMicrosecondsApartReplays) {
  std::vector<TraceRow> rows;
  const double times_s[] = {1.000000, 1.0020001, 1.0020004, 1.0020008, 1.003};  // a late tick, then catch-up
  for (int k = 0; k < 5; ++k)
    rows.push_back({times_s[k], Eigen::Vector3d(0.0, 0.0, -1e-4 * k), Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), -1.0, -1.0, 0, "press", 0,
                    WatchdogState::kNoModel, static_cast<std::uint64_t>(k), true, false, Eigen::Vector3d::Zero()});
  const std::string path =
      (std::filesystem::temp_directory_path() / ("hapsim_trace_" + std::to_string(::getpid()) + ".csv")).string();
  ASSERT_TRUE(WriteTraceCsv(path, rows));
  const std::vector<PoseLogRow> log = LoadPoseLog(path);
  std::remove(path.c_str());
  ASSERT_EQ(log.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(log[static_cast<std::size_t>(k)].t_s, times_s[k], 1e-9);
    EXPECT_NEAR(log[static_cast<std::size_t>(k)].tip_W_m.z(), -1e-4 * k, 1e-12);
  }
  ReplayDevice replay(log);
  EXPECT_NEAR(replay.Read(0.0020004).tip_W_m.z(), -2e-4, 1e-9);  // the second catch-up pose, on time
}

TEST(ReplayDevice, MalformedLogsNameTheLine) {
  try {
    ParsePoseLog("header\n0,0,0,0,1,0,0,0\n0.1,0,nan,0,1,0,0,0\n");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParsePoseLog("h\n0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n"), std::invalid_argument);  // t not increasing
  EXPECT_THROW(ParsePoseLog("h\n0,0,0,0,2,0,0,0\n"), std::invalid_argument);                   // not unit
  EXPECT_THROW(ParsePoseLog("h\n0,0,0\n"), std::invalid_argument);                             // short row
  EXPECT_THROW(ParsePoseLog("h\n"), std::invalid_argument);                                    // empty
}

}  // namespace
}  // namespace hapsim::bridge
