// A trial's automatic metrics (for the instructor's assessment), accumulated
// on the session's tick from what the scene reports each tick. A trial runs from
// the session's creation or its last reset to the next reset or its close.
//
//   every scene   duration, time to first contact, peak |tool force|, deepest tip
//   acupuncture   layers pierced (puncture events), peak |force| while the tip was
//                 in or on each layer, target depth error = deepest tip - target
//   cutting       incision length (sum of cut_end events), deviation of the tip
//                 from the target line while cutting (max and mean, in the skin plane)
//   vessel        peak force, deepest indentation (the tip's depth below the crest)
//
// Fixed-size and allocation-free: OnTick runs on the 1 kHz tick.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include <Eigen/Core>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

// What a trial is measured against (from the class config; NaN: none).
struct TrialTargets {
  double depth_m = std::numeric_limits<double>::quiet_NaN();  // acupuncture: target needle depth
  // cutting: the planned incision, from (x0, y0) to (x1, y1) in the skin plane [m]
  std::array<double, 4> line_m = {std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0, 0.0};
  bool has_line() const { return !std::isnan(line_m[0]); }
};

struct TrialStats {
  static constexpr int kMaxLayers = 8;
  std::uint64_t trial = 0;          // 0 for the first trial of a session, +1 per reset
  double start_sim_s = 0.0;
  double last_sim_s = 0.0;
  double first_contact_sim_s = std::numeric_limits<double>::quiet_NaN();
  double peak_force_N = 0.0;
  double max_tip_depth_m = 0.0;
  std::array<double, kMaxLayers> peak_force_in_layer_N{};  // by layer index
  std::uint32_t layers_pierced_mask = 0;                   // bit L: layer L punctured
  std::uint32_t punctures = 0;
  std::uint32_t cuts = 0;
  double incision_length_m = 0.0;
  double line_deviation_max_m = 0.0;  // while cutting, distance of the tip from the target line
  double line_deviation_sum_m = 0.0;
  std::uint64_t cutting_ticks = 0;
  std::uint64_t ticks = 0;

  double duration_s() const { return last_sim_s - start_sim_s; }
  double line_deviation_mean_m() const {
    return cutting_ticks ? line_deviation_sum_m / static_cast<double>(cutting_ticks) : 0.0;
  }
};

// One tick's view of the scene.
struct TrialTick {
  double sim_time_s = 0.0;
  double force_N = 0.0;  // |force of the tissue on the tool|
  int current_layer = -1;
  double tip_depth_m = 0.0;
  core::ContactState contact = core::ContactState::kFree;
  Eigen::Vector3d tip_W_m = Eigen::Vector3d::Zero();
  bool tool_present = false;
  std::span<const core::SceneEvent> new_events;  // logged since the previous tick
};

class TrialTracker {
 public:
  // first_trial: the number of the trial that starts now (a session brought
  // back after a restart goes on counting from its recording's trial).
  explicit TrialTracker(TrialTargets targets = {}, std::uint64_t first_trial = 0) : targets_(targets) {
    stats_.trial = first_trial;
  }
  const TrialTargets& targets() const { return targets_; }
  const TrialStats& stats() const { return stats_; }
  void OnTick(const TrialTick& tick);
  // Ends the trial (a reset) and returns its stats; the next trial starts at
  // the next OnTick.
  TrialStats StartNext();

 private:
  TrialTargets targets_;
  TrialStats stats_;
  bool started_ = false;
};

// Distance [m] from (x, y) to the segment (x0, y0)-(x1, y1).
double DistanceToSegment(double x, double y, const std::array<double, 4>& segment);

}  // namespace hapsim::service
