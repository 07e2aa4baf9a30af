// A trial's automatic metrics from known tick sequences: every number below
// follows from the ticks fed in by hand.
#include "hapsim/classroom/trial_tracker.h"

#include <gtest/gtest.h>

#include <vector>

#include "hapsim/classroom/trial_book.h"

namespace hapsim::service {
namespace {

using core::ContactState;
using core::SceneEvent;
using core::SceneEventKind;

TrialTick Tick(double t, double force, int layer, double depth, ContactState contact,
               Eigen::Vector3d tip = Eigen::Vector3d::Zero(), std::span<const SceneEvent> events = {}) {
  TrialTick k;
  k.sim_time_s = t;
  k.force_N = force;
  k.current_layer = layer;
  k.tip_depth_m = depth;
  k.contact = contact;
  k.tip_W_m = tip;
  k.tool_present = true;
  k.new_events = events;
  return k;
}

// A needle: free until t = 0.2 s, presses the skin (layer 0) up to 0.5 N,
// punctures it, then pushes in the fat (layer 1) up to 0.8 N at 12 mm.
TEST(TrialTracker, NeedleTrialGivesLayersPeaksDepthAndTimes) {
  TrialTargets targets;
  targets.depth_m = 0.010;
  TrialTracker tracker(targets);
  TrialTick absent = Tick(0.0, 9.0, 0, 0.05, ContactState::kContact);
  absent.tool_present = false;  // no device: a stray force counts for nothing
  tracker.OnTick(absent);
  tracker.OnTick(Tick(0.1, 0.0, -1, 0.0, ContactState::kFree));
  tracker.OnTick(Tick(0.2, 0.1, 0, 0.001, ContactState::kContact));
  tracker.OnTick(Tick(0.3, 0.5, 0, 0.003, ContactState::kContact));
  const SceneEvent puncture{.t_s = 0.35, .kind = SceneEventKind::kPuncture, .layer = 0};
  tracker.OnTick(Tick(0.4, 0.2, 1, 0.004, ContactState::kPunctured, Eigen::Vector3d::Zero(), {&puncture, 1}));
  tracker.OnTick(Tick(0.5, 0.8, 1, 0.012, ContactState::kPunctured));
  tracker.OnTick(Tick(0.6, 0.3, 1, 0.011, ContactState::kPunctured));
  const TrialStats& s = tracker.stats();
  EXPECT_DOUBLE_EQ(s.duration_s(), 0.6);
  EXPECT_DOUBLE_EQ(s.first_contact_sim_s - s.start_sim_s, 0.2);
  EXPECT_DOUBLE_EQ(s.peak_force_N, 0.8);
  EXPECT_DOUBLE_EQ(s.max_tip_depth_m, 0.012);
  EXPECT_DOUBLE_EQ(s.peak_force_in_layer_N[0], 0.5);
  EXPECT_DOUBLE_EQ(s.peak_force_in_layer_N[1], 0.8);
  EXPECT_EQ(s.layers_pierced_mask, 1u);
  EXPECT_EQ(s.punctures, 1u);

  TrialRecord r;
  r.session_id = "t1";
  r.trainee = "alice";
  r.scene = "acupuncture";
  r.layer_names = {"skin", "fat", "muscle"};
  r.targets = targets;
  r.stats = s;
  r.end = "reset";
  const std::string csv = FormatTrialsCsv({r}, [](const std::string&) { return std::string("6.7900"); });
  const std::string row = csv.substr(csv.find('\n') + 1);
  // depth error = 12 - 10 mm; peaks by layer name; score from the callback.
  EXPECT_EQ(row,
            "t1,alice,acupuncture,0,reset,0.600,0.200,0.8000,12.000,10.000,2.000,skin,1,skin=0.5000;fat=0.8000,0,"
            "0.000,,,6.7900\n");
}

// A cut along y = 0 planned from x = -10 mm to +10 mm: the tip cuts at
// y = 1 mm and 3 mm, then 2 mm past the end (distance 2 mm to the end
// point); outside "cutting" the tip's distance does not count.
TEST(TrialTracker, CutTrialGivesIncisionLengthAndLineDeviation) {
  TrialTargets targets;
  targets.line_m = {-0.010, 0.0, 0.010, 0.0};
  TrialTracker tracker(targets);
  tracker.OnTick(Tick(0.0, 0.1, -1, 0.0, ContactState::kContact, {0.0, 0.05, 0.0}));  // far off, not cutting
  tracker.OnTick(Tick(0.1, 0.2, -1, 0.001, ContactState::kCutting, {-0.005, 0.001, 0.0}));
  tracker.OnTick(Tick(0.2, 0.2, -1, 0.001, ContactState::kCutting, {0.000, 0.003, 0.0}));
  const SceneEvent cut_end{.t_s = 0.3, .kind = SceneEventKind::kCutEnd, .value = 0.017};
  tracker.OnTick(Tick(0.3, 0.2, -1, 0.001, ContactState::kCutting, {0.012, 0.0, 0.0}, {&cut_end, 1}));
  const TrialStats& s = tracker.stats();
  EXPECT_NEAR(s.line_deviation_max_m, 0.003, 1e-15);
  EXPECT_NEAR(s.line_deviation_mean_m(), (0.001 + 0.003 + 0.002) / 3.0, 1e-15);
  EXPECT_EQ(s.cuts, 1u);
  EXPECT_DOUBLE_EQ(s.incision_length_m, 0.017);
}

TEST(TrialTracker, AResetEndsTheTrialAndTheNextStartsAtItsFirstTick) {
  TrialTracker tracker;
  tracker.OnTick(Tick(1.0, 0.4, 0, 0.002, ContactState::kContact));
  tracker.OnTick(Tick(2.0, 0.1, 0, 0.001, ContactState::kContact));
  const TrialStats ended = tracker.StartNext();
  EXPECT_EQ(ended.trial, 0u);
  EXPECT_DOUBLE_EQ(ended.duration_s(), 1.0);
  EXPECT_DOUBLE_EQ(ended.peak_force_N, 0.4);
  tracker.OnTick(Tick(0.001, 0.05, -1, 0.0, ContactState::kFree));  // sim time restarts after a reset
  EXPECT_EQ(tracker.stats().trial, 1u);
  EXPECT_DOUBLE_EQ(tracker.stats().start_sim_s, 0.001);
  EXPECT_DOUBLE_EQ(tracker.stats().peak_force_N, 0.05);
}

TEST(TrialTracker, DistanceToSegmentIsPerpendicularInsideAndToTheEndOutside) {
  const std::array<double, 4> s = {0.0, 0.0, 3.0, 0.0};
  EXPECT_DOUBLE_EQ(DistanceToSegment(1.0, 2.0, s), 2.0);
  EXPECT_DOUBLE_EQ(DistanceToSegment(6.0, 4.0, s), 5.0);    // 3-4-5 from the end (3, 0)
  EXPECT_DOUBLE_EQ(DistanceToSegment(-3.0, -4.0, s), 5.0);  // from the start
  EXPECT_DOUBLE_EQ(DistanceToSegment(1.0, 1.0, {2.0, 2.0, 2.0, 2.0}), std::sqrt(2.0));  // a point
}

}  // namespace
}  // namespace hapsim::service
