#include "hapsim/core/scenes/vessel/vessel_settled_curve.h"

#include <algorithm>
#include <cmath>

namespace hapsim::core {
namespace {

// The segment [k, k+1] holding depth_m, clamped to the curve's ends.
std::size_t SegmentOf(const VesselSettledCurve& c, double depth_m) {
  const double last = static_cast<double>(c.force_N.size() - 2);
  const double k = std::clamp(depth_m / c.step_m, 0.0, last);
  return static_cast<std::size_t>(k);
}

}  // namespace

double VesselSettledCurve::ForceAt_N(double depth_m) const {
  if (Empty()) return 0.0;
  const std::size_t k = SegmentOf(*this, depth_m);
  const double t = depth_m / step_m - static_cast<double>(k);
  return force_N[k] + t * (force_N[k + 1] - force_N[k]);
}

double VesselSettledCurve::DepthAtForce_m(double level_N) const {
  if (Empty() || level_N <= force_N[0]) return 0.0;
  for (std::size_t k = 0; k + 1 < force_N.size(); ++k) {
    const double lo = force_N[k], hi = force_N[k + 1];
    if (level_N <= hi && hi > lo) return step_m * (static_cast<double>(k) + (level_N - lo) / (hi - lo));
  }
  const std::size_t k = force_N.size() - 2;
  const double rise = force_N[k + 1] - force_N[k];
  return rise > 0.0 ? step_m * (static_cast<double>(k) + (level_N - force_N[k]) / rise) : MaxDepth_m();
}

double VesselSettledCurve::SlopeAt_N_per_m(double depth_m, double min_N_per_m) const {
  if (Empty()) return min_N_per_m;
  // Central difference over +-3 samples around the nearest (one-sided at
  // the ends): the node lattice makes the slope wiggle by +-30 % from one
  // 0.1 mm to the next on the vein; the device renders the trend over
  // +-0.3 mm.
  const auto last = static_cast<double>(force_N.size() - 1);
  const auto k = static_cast<std::size_t>(std::clamp(std::round(depth_m / step_m), 0.0, last));
  const std::size_t lo = k < 3 ? 0 : k - 3, hi = std::min(k + 3, force_N.size() - 1);
  return std::max(min_N_per_m, (force_N[hi] - force_N[lo]) / (static_cast<double>(hi - lo) * step_m));
}

}  // namespace hapsim::core
