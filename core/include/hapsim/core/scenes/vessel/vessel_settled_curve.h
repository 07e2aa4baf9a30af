// The force-depth relation of a vessel's wall pressed quasi-statically by the
// probe: the settled contact force at evenly spaced depths into the rest wall.
// The vessel scene takes the stiffness it sends to the device from this
// curve's slope at the tip's depth, so the device renders the wall the
// physics settles to, not the transient of the last ticks.
#pragma once
#include <vector>

namespace hapsim::core {

struct VesselSettledCurve {
  double step_m = 0.0;          // depth between samples
  std::vector<double> force_N;  // force_N[k]: settled force at depth k step_m (force_N[0] = 0 at first touch)

  bool Empty() const { return force_N.size() < 2; }
  double MaxDepth_m() const { return step_m * static_cast<double>(force_N.size() - 1); }
  // Linear interpolation between samples; past the last, the last segment extended.
  double ForceAt_N(double depth_m) const;
  // The depth at which the curve reaches force_N (the first crossing;
  // linear between samples; past the last sample, the last segment extended).
  double DepthAtForce_m(double level_N) const;
  // Slope dF/d(depth) [N/m] at depth_m: the central difference over +-3
  // samples around the nearest (one-sided at the curve's ends), never below
  // min_N_per_m.
  double SlopeAt_N_per_m(double depth_m, double min_N_per_m) const;
};

}  // namespace hapsim::core
