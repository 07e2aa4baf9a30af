#include "hapsim/core/scenes/vessel/vessel_settled_curve.h"

#include <algorithm>

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

double VesselSettledCurve::SlopeAt_N_per_m(double depth_m, double min_N_per_m) const {
  if (Empty()) return min_N_per_m;
  const std::size_t k = SegmentOf(*this, depth_m);
  return std::max(min_N_per_m, (force_N[k + 1] - force_N[k]) / step_m);
}

}  // namespace hapsim::core
