#include "hapsim/classroom/trial_tracker.h"

#include <algorithm>

#include "hapsim/core/math/portable_math.h"

namespace hapsim::service {

double DistanceToSegment(double x, double y, const std::array<double, 4>& s) {
  const double dx = s[2] - s[0], dy = s[3] - s[1];
  const double length2 = dx * dx + dy * dy;
  double t = length2 > 0.0 ? ((x - s[0]) * dx + (y - s[1]) * dy) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return core::pmath::Hypot(x - (s[0] + t * dx), y - (s[1] + t * dy));
}

void TrialTracker::OnTick(const TrialTick& tick) {
  TrialStats& s = stats_;
  if (!started_) {
    started_ = true;
    s.start_sim_s = tick.sim_time_s;
  }
  ++s.ticks;
  s.last_sim_s = tick.sim_time_s;
  if (!tick.tool_present) return;  // no device: nothing the trainee did
  s.peak_force_N = std::max(s.peak_force_N, tick.force_N);
  s.max_tip_depth_m = std::max(s.max_tip_depth_m, tick.tip_depth_m);
  if (tick.contact != core::ContactState::kFree && std::isnan(s.first_contact_sim_s)) {
    s.first_contact_sim_s = tick.sim_time_s;
  }
  if (tick.current_layer >= 0 && tick.current_layer < TrialStats::kMaxLayers) {
    auto& peak = s.peak_force_in_layer_N[static_cast<std::size_t>(tick.current_layer)];
    peak = std::max(peak, tick.force_N);
  }
  if (tick.contact == core::ContactState::kCutting && targets_.has_line()) {
    const double d = DistanceToSegment(tick.tip_W_m.x(), tick.tip_W_m.y(), targets_.line_m);
    s.line_deviation_max_m = std::max(s.line_deviation_max_m, d);
    s.line_deviation_sum_m += d;
    ++s.cutting_ticks;
  }
  for (const core::SceneEvent& e : tick.new_events) {
    switch (e.kind) {
      case core::SceneEventKind::kPuncture:
        ++s.punctures;
        if (e.layer >= 0 && e.layer < 32) s.layers_pierced_mask |= 1u << e.layer;
        break;
      case core::SceneEventKind::kCutEnd:
        ++s.cuts;
        s.incision_length_m += e.value;
        break;
      default: break;
    }
  }
}

TrialStats TrialTracker::StartNext() {
  const TrialStats finished = stats_;
  stats_ = TrialStats{};
  stats_.trial = finished.trial + 1;
  started_ = false;  // the next trial starts at the next tick's sim time
  return finished;
}

}  // namespace hapsim::service
