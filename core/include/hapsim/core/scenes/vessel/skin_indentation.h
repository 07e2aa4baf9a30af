// The skin and subcutis a probe indents, as an elastic half-space: the
// probe's sphere (radius R) presses it as Hertz found, F = 4/3 E* sqrt(R)
// d^(3/2); once the sphere is in (d > R) its shaft of the same radius goes on
// as a flat punch, F = 4/3 E* R^2 + 2 E* R (d - R) — the force and its slope
// (2 E* R) are continuous there. E* = E / (1 - nu^2). Used in parallel with
// the vessel under the skin (vessel_scene.h).
#pragma once
#include <cmath>

namespace hapsim::core {

// Force [N] at depth d [m] below the surface; 0 above it.
inline double SkinIndentationForce_N(double depth_m, double probe_radius_m, double youngs_modulus_Pa,
                                     double poisson_ratio) {
  if (!(depth_m > 0.0)) return 0.0;
  const double e_star_Pa = youngs_modulus_Pa / (1.0 - poisson_ratio * poisson_ratio);
  const double r = probe_radius_m;
  if (depth_m <= r) return 4.0 / 3.0 * e_star_Pa * std::sqrt(r) * depth_m * std::sqrt(depth_m);
  return 4.0 / 3.0 * e_star_Pa * r * r + 2.0 * e_star_Pa * r * (depth_m - r);
}

}  // namespace hapsim::core
