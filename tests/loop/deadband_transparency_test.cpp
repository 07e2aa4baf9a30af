// Perceptual deadband coding against the every-tick stream, on the same
// scripted motion through the same loop (HapticLoop: no scheduling noise):
// the force the device renders with both deadbands on stays within the
// force JND of the every-tick stream's, and few packets go out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <ostream>
#include <string>

#include "loop/haptic_loop.h"

namespace hapsim::test {
namespace {

constexpr double kJnd = 0.07;          // Weber fraction for force (Hinterseer et al.)
constexpr double kJndFloorN = 0.05;    // below this force, differences are judged against it
constexpr double kActiveShare = 0.01;  // ticks where either stream pushes more than this share of its peak

struct ScriptedScene {
  std::string scene;
  bridge::SyntheticScript script;
  double seconds;
};

// The deadband benchmark's scripts (tests/bench/deadband.sh): one press through each scene's layers.
ScriptedScene Insertion(const std::string& scene, double depth_m, double hold_s, double seconds) {
  bridge::SyntheticScript s;
  s.kind = "insertion";
  s.depth_m = depth_m;
  s.speed_m_per_s = 0.01;
  s.hold_s = hold_s;
  s.start_height_m = 0.01;
  return {scene, s, seconds};
}

ScriptedScene Cut() {
  bridge::SyntheticScript s;
  s.kind = "cut";
  s.depth_m = 0.0015;
  s.speed_m_per_s = 0.005;
  s.entry_W_m = Eigen::Vector3d(-0.006, 0.0, 0.0);
  s.cut_length_m = 0.012;
  s.start_height_m = 0.01;
  return {"cutting", s, 7.5};
}

HapticLoopConfig LoopFor(const ScriptedScene& s) {
  HapticLoopConfig config;
  config.scene = s.scene;
  config.script = s.script;
  config.seconds = s.seconds;
  return config;
}

struct Agreement {
  int compared = 0;
  int within = 0;
  int missed_where_passivity_acted = 0;
  double worst_N = 0.0;
  double share() const { return compared ? static_cast<double>(within) / compared : 0.0; }
  // Misses the deadband's coding leaves, without those where a passivity
  // controller changed the force (each acts on its own run's energy).
  double share_besides_passivity() const {
    return compared ? 1.0 - static_cast<double>(compared - within - missed_where_passivity_acted) / compared : 0.0;
  }
};

// Tick by tick: is `sparse` within the force JND of `every`? force: the
// rendered force (after the safety chain) or the models' own force at the
// stylus (before it: the coding alone).
template <class Force>
Agreement Compare(const HapticLoopRun& every, const HapticLoopRun& sparse, Force force) {
  const std::size_t n = std::min(every.ticks.size(), sparse.ticks.size());
  double peak_N = 0.0;
  for (std::size_t k = 0; k < n; ++k)
    peak_N = std::max({peak_N, force(every.ticks[k]).norm(), force(sparse.ticks[k]).norm()});
  Agreement a;
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d f_every = force(every.ticks[k]);
    const Eigen::Vector3d f_sparse = force(sparse.ticks[k]);
    if (std::max(f_every.norm(), f_sparse.norm()) <= kActiveShare * peak_N) continue;
    ++a.compared;
    const double diff_N = (f_every - f_sparse).norm();
    const bool within = diff_N <= kJnd * std::max(f_every.norm(), kJndFloorN);
    a.within += within;
    if (!within && (every.ticks[k].passivity_acted || sparse.ticks[k].passivity_acted))
      ++a.missed_where_passivity_acted;
    a.worst_N = std::max(a.worst_N, diff_N);
  }
  return a;
}

Eigen::Vector3d Rendered(const LoopTick& t) { return t.force_W_N; }
Eigen::Vector3d Requested(const LoopTick& t) { return t.requested_W_N; }

// Share of ticks (of a phase, or all) where `happened` (a pose sent, a model taken).
double ShareOfTicks(const HapticLoopRun& run, bool LoopTick::*happened, const char* phase) {
  int n = 0, count = 0;
  for (const LoopTick& t : run.ticks) {
    if (phase && t.phase != phase) continue;
    ++n;
    count += t.*happened;
  }
  return n ? static_cast<double>(count) / n : 0.0;
}
double PoseShare(const HapticLoopRun& run, const char* phase = nullptr) {
  return ShareOfTicks(run, &LoopTick::pose_sent, phase);
}
double ModelShare(const HapticLoopRun& run, const char* phase = nullptr) {
  return ShareOfTicks(run, &LoopTick::model_taken, phase);
}

void PrintTo(const ScriptedScene& s, std::ostream* os) { *os << s.scene; }

class DeadbandTransparency : public ::testing::TestWithParam<ScriptedScene> {
 protected:
  void SetUp() override {
    HapticLoopConfig every = LoopFor(GetParam());
    every.session.model_deadband.jnd = 0.0;
    every.channel.pose_deadband.position_m = 0.0;
    HapticLoopConfig sparse = LoopFor(GetParam());
    sparse.session.model_deadband.jnd = kJnd;
    sparse.channel.pose_deadband.position_m = 0.00005;
    every_ = RunHapticLoop(every);
    sparse_ = RunHapticLoop(sparse);
  }
  HapticLoopRun every_, sparse_;
};

// The models the deadband lets out, evaluated at the stylus, against the
// every-tick stream's: the coding's own error.
TEST_P(DeadbandTransparency, TheHeldModelsStayWithinTheForceJndOfTheEveryTickModels) {
  const Agreement a = Compare(every_, sparse_, Requested);
  std::printf("%s: models' force within the JND in %.2f %% of %d ticks (largest difference %.3f N)\n",
              GetParam().scene.c_str(), 100.0 * a.share(), a.compared, a.worst_N);
  EXPECT_GE(a.share(), 0.99);
}

// The force the device renders, after the whole safety chain. A passivity
// controller acts on the energy its run has stored so far (fading the push
// as the reserve runs out), so where either run's acts the two part by as
// much as their reserves differ: those ticks are counted apart. Every other
// tick must be within the JND, and all of them where no controller acts.
TEST_P(DeadbandTransparency, TheRenderedForceStaysWithinTheForceJndOfTheEveryTickStream) {
  const Agreement a = Compare(every_, sparse_, Rendered);
  std::printf(
      "%s: rendered force within the JND in %.2f %% of %d ticks (largest difference %.3f N); %d of the "
      "misses where a passivity controller acted\n",
      GetParam().scene.c_str(), 100.0 * a.share(), a.compared, a.worst_N, a.missed_where_passivity_acted);
  EXPECT_GE(a.share_besides_passivity(), 0.99);
  if (GetParam().scene == "acupuncture" || GetParam().scene == "cutting") {
    EXPECT_GE(a.share(), 0.99);  // presses whose reserve never runs out
  }
}

// Packets: <= 5 % of ticks per direction while the tool holds still in the
// tissue, <= 20 % over the whole script.
TEST_P(DeadbandTransparency, SendsFewPosesAndModels) {
  std::printf("%s: poses %.1f %% of ticks (holding %.1f %%), models %.1f %% (holding %.1f %%)\n",
              GetParam().scene.c_str(), 100.0 * PoseShare(sparse_), 100.0 * PoseShare(sparse_, "hold"),
              100.0 * ModelShare(sparse_), 100.0 * ModelShare(sparse_, "hold"));
  EXPECT_LE(PoseShare(sparse_), 0.20);
  EXPECT_LE(ModelShare(sparse_), 0.20);
  if (GetParam().scene != "cutting") {  // the cut has no hold
    EXPECT_LE(PoseShare(sparse_, "hold"), 0.05);
    EXPECT_LE(ModelShare(sparse_, "hold"), 0.05);
  }
  EXPECT_GE(PoseShare(every_), 0.999);  // the control: every tick
  EXPECT_GE(ModelShare(every_), 0.999);
}

// Models 25 ms apart are what the server promised: the device's watchdog
// does not take a keep-alive gap for a late stream.
TEST_P(DeadbandTransparency, TheWatchdogTakesKeepAliveGapsForWhatTheServerPromised) {
  EXPECT_EQ(sparse_.safety.warnings, 0u);
  EXPECT_EQ(sparse_.safety.delay_warnings, 0u);
  EXPECT_EQ(sparse_.safety.fades, 0u);
}

INSTANTIATE_TEST_SUITE_P(Scenes, DeadbandTransparency,
                         ::testing::Values(Insertion("tissue_block", 0.005, 1.0, 4.5),
                                           Insertion("acupuncture", 0.014, 1.0, 6.3),
                                           Insertion("vessel", 0.002, 1.0, 3.9), Cut()),
                         [](const auto& test_info) { return test_info.param.scene; });

}  // namespace
}  // namespace hapsim::test
