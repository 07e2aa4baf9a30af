// The passivity controller on a long link: the scripted presses of every
// scene with models one round trip late (0 to 1000 ms), every pose and
// every model sent. The observer's E — the energy the rendering has absorbed
// from the hand — never falls below zero: no tick gives the hand energy it
// never put in, however stale the models.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "loop/haptic_loop.h"

namespace hapsim::test {
namespace {

constexpr double kEnergyRoundingJ = 1e-15;  // sums of ~1e-5 J terms

struct DelayedPress {
  std::string scene;
  int one_way_ms;
};

void PrintTo(const DelayedPress& p, std::ostream* os) { *os << p.scene << " " << 2 * p.one_way_ms << " ms"; }

HapticLoopConfig PressOf(const DelayedPress& p) {
  HapticLoopConfig c;
  c.scene = p.scene;
  c.one_way_delay_ticks = p.one_way_ms;
  bridge::SyntheticScript& s = c.script;
  s.start_height_m = 0.01;
  const double round_trip_s = 2e-3 * p.one_way_ms;
  if (p.scene == "cutting") {  // approach, press 1.5 mm, a 12 mm stroke, lift, at 5 mm/s
    s.kind = "cut";
    s.depth_m = 0.0015;
    s.speed_m_per_s = 0.005;
    s.entry_W_m = Eigen::Vector3d(-0.006, 0.0, 0.0);
    s.cut_length_m = 0.012;
    c.seconds = (2 * 0.01 + 2 * 0.0015 + 0.012) / 0.005 + round_trip_s + 0.5;
  } else {  // one insertion at 10 mm/s, held until the models of the press have come back
    s.kind = "insertion";
    s.depth_m = p.scene == "acupuncture" ? 0.014 : p.scene == "vessel" ? 0.002 : 0.005;
    s.speed_m_per_s = 0.01;
    s.hold_s = 0.5 + round_trip_s;
    c.seconds = 2 * (0.01 + s.depth_m) / 0.01 + s.hold_s + round_trip_s + 0.3;
  }
  return c;
}

class PassivityUnderDelay : public ::testing::TestWithParam<DelayedPress> {};

TEST_P(PassivityUnderDelay, NoTickGivesTheHandEnergyItNeverPutIn) {
  const HapticLoopRun run = RunHapticLoop(PressOf(GetParam()));
  double lowest_J = 0.0, peak_N = 0.0, largest_step_N = 0.0;
  for (std::size_t k = 0; k < run.ticks.size(); ++k) {
    const LoopTick& t = run.ticks[k];
    lowest_J = std::min(lowest_J, t.passivity_energy_J);
    peak_N = std::max(peak_N, t.force_W_N.norm());
    // The controller's own steps: the rendered force's change on a tick it
    // acted, beyond the change of what the models asked for.
    if (k > 0 && t.passivity_acted) {
      const LoopTick& before = run.ticks[k - 1];
      const double step_N = (t.force_W_N - before.force_W_N).norm();
      const double asked_N = (t.requested_W_N - before.requested_W_N).norm();
      largest_step_N = std::max(largest_step_N, step_N - asked_N);
    }
  }
  std::printf(
      "%s, %d ms round trip: peak %.3f N, lowest E %.2e J, corrected %llu, bounded %llu, uncorrected %llu, "
      "largest step of the controller %.1f %% of the peak\n",
      GetParam().scene.c_str(), 2 * GetParam().one_way_ms, peak_N, lowest_J,
      static_cast<unsigned long long>(run.safety.passivity_corrected),
      static_cast<unsigned long long>(run.safety.passivity_bounded),
      static_cast<unsigned long long>(run.safety.passivity_uncorrected), 100.0 * largest_step_N / peak_N);
  EXPECT_GT(peak_N, 0.1);  // the press was felt
  EXPECT_GE(lowest_J, -kEnergyRoundingJ);
  EXPECT_EQ(run.safety.passivity_uncorrected, 0u);
}

std::vector<DelayedPress> AllPresses() {
  std::vector<DelayedPress> all;
  for (const char* scene : {"tissue_block", "acupuncture", "vessel", "cutting"})
    for (int one_way_ms : {0, 10, 100, 500}) all.push_back({scene, one_way_ms});
  return all;
}

INSTANTIATE_TEST_SUITE_P(Scenes, PassivityUnderDelay, ::testing::ValuesIn(AllPresses()), [](const auto& test_info) {
  return test_info.param.scene + "_" + std::to_string(2 * test_info.param.one_way_ms) + "ms";
});

}  // namespace
}  // namespace hapsim::test
