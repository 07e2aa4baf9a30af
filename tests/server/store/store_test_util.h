// Helpers shared by the store's tests: a temp directory per test, sample
// rows with awkward values, and NaN-aware exact comparisons.
#pragma once
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include "hapsim/store/results_store.h"

namespace hapsim::service::store_test {

// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = std::string("hapsim-store-") + (info ? info->name() : "test") + "-" +
                             std::to_string(::getpid()) + "-" + std::to_string(counter++);
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string File(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Bit-for-bit equal, or both NaN (a NULL column reads back as NaN).
inline bool SameDouble(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// A trial with values that do not survive a careless round trip: 0.1, 1/3,
// tiny and huge magnitudes, a NaN first contact, odd layer names.
inline StoredTrial SampleTrial(const std::string& session, std::uint64_t trial, const std::string& run = "run-1") {
  StoredTrial t;
  TrialRecord& r = t.record;
  r.session_id = session;
  r.trainee = "alice";
  r.scene = "acupuncture";
  r.layer_names = {"skin", "fat|subcutis", "muscle 50%"};
  r.targets.depth_m = 0.012;
  r.end = "running";
  TrialStats& s = r.stats;
  s.trial = trial;
  s.start_sim_s = 0.1 * static_cast<double>(trial + 1);
  s.last_sim_s = s.start_sim_s + 1.0 / 3.0;
  s.first_contact_sim_s = kNaN;
  s.peak_force_N = 2.718281828459045;
  s.max_tip_depth_m = 1e-300;
  s.peak_force_in_layer_N = {0.1, 0.2, 1.0 / 7.0, 0, 0, 0, 0, 1e300};
  s.layers_pierced_mask = 0b101;
  s.punctures = 2;
  s.cuts = 3;
  s.incision_length_m = 0.0123456789012345678;
  s.line_deviation_max_m = 0.001;
  s.line_deviation_sum_m = 0.0333;
  s.cutting_ticks = 77;
  s.ticks = 1234567;
  t.run_id = run;
  t.class_name = "acu-101";
  t.recording_path = "/var/lib/hapsim/rec/" + session + "/" + run + "-t" + std::to_string(trial) + ".hrec";
  t.updated_unix_ms = 1700000000123;
  return t;
}

inline void ExpectSameTrial(const StoredTrial& got, const StoredTrial& want) {
  const TrialRecord& g = got.record;
  const TrialRecord& w = want.record;
  EXPECT_EQ(g.session_id, w.session_id);
  EXPECT_EQ(g.trainee, w.trainee);
  EXPECT_EQ(g.scene, w.scene);
  EXPECT_EQ(g.layer_names, w.layer_names);
  EXPECT_EQ(g.end, w.end);
  EXPECT_TRUE(SameDouble(g.targets.depth_m, w.targets.depth_m)) << g.targets.depth_m;
  EXPECT_EQ(g.targets.has_line(), w.targets.has_line());
  if (w.targets.has_line()) {
    for (int i = 0; i < 4; ++i) EXPECT_EQ(g.targets.line_m[i], w.targets.line_m[i]) << i;
  }
  const TrialStats& gs = g.stats;
  const TrialStats& ws = w.stats;
  EXPECT_EQ(gs.trial, ws.trial);
  EXPECT_TRUE(SameDouble(gs.start_sim_s, ws.start_sim_s));
  EXPECT_TRUE(SameDouble(gs.last_sim_s, ws.last_sim_s));
  EXPECT_TRUE(SameDouble(gs.first_contact_sim_s, ws.first_contact_sim_s)) << gs.first_contact_sim_s;
  EXPECT_TRUE(SameDouble(gs.peak_force_N, ws.peak_force_N));
  EXPECT_TRUE(SameDouble(gs.max_tip_depth_m, ws.max_tip_depth_m));
  for (int l = 0; l < TrialStats::kMaxLayers; ++l) {
    EXPECT_TRUE(SameDouble(gs.peak_force_in_layer_N[l], ws.peak_force_in_layer_N[l])) << "layer " << l;
  }
  EXPECT_EQ(gs.layers_pierced_mask, ws.layers_pierced_mask);
  EXPECT_EQ(gs.punctures, ws.punctures);
  EXPECT_EQ(gs.cuts, ws.cuts);
  EXPECT_TRUE(SameDouble(gs.incision_length_m, ws.incision_length_m));
  EXPECT_TRUE(SameDouble(gs.line_deviation_max_m, ws.line_deviation_max_m));
  EXPECT_TRUE(SameDouble(gs.line_deviation_sum_m, ws.line_deviation_sum_m));
  EXPECT_EQ(gs.cutting_ticks, ws.cutting_ticks);
  EXPECT_EQ(gs.ticks, ws.ticks);
  EXPECT_EQ(got.run_id, want.run_id);
  EXPECT_EQ(got.class_name, want.class_name);
  EXPECT_EQ(got.recording_path, want.recording_path);
  EXPECT_EQ(got.updated_unix_ms, want.updated_unix_ms);
}

inline StoredRecording SampleRecording(const std::string& session, std::uint64_t trial, std::int64_t started_ms) {
  StoredRecording r;
  r.path = "/rec/" + session + "/run-1-t" + std::to_string(trial) + ".hrec";
  r.session_id = session;
  r.run_id = "run-1";
  r.trial = trial;
  r.trainee = "bob";
  r.class_name = "cut-201";
  r.scene = "cutting";
  r.started_unix_ms = started_ms;
  r.ticks = 1000 * (trial + 1);
  r.bytes = 4096 * (trial + 1);
  return r;
}

}  // namespace hapsim::service::store_test
