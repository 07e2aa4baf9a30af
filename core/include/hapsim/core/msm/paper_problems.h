// The two test problems of the gingival-tissue paper (Li et al. 2020), with closed
// forms, shared by `hapsim-validate integrators` and the tests.
#pragma once
#include <cmath>
#include <utility>

#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/msm/particle_steppers.h"

namespace hapsim::core::paper {

// Eq. (1): y' = -y + 2x + 3, y(0) = 0, h = 0.05 on [0, 1];
// exact y = 2x + 1 + (y0 - 1) e^-x = 2x + 1 - e^-x  (y0 = 1 would make every
// method exact, so y0 = 0).
struct LinearOde {
  static constexpr double kY0 = 0.0;
  static constexpr double kH = 0.05;
  static constexpr double kXEnd = 1.0;
  static double F(double x, double y) { return -y + 2.0 * x + 3.0; }
  static double Exact(double x) { return 2.0 * x + 1.0 + (kY0 - 1.0) * pmath::Exp(-x); }
};

// The damped particle: the paper gives no numbers, so: m = 2 kg (not 1, so a
// missing /m shows), k = 8 N/m (w0 = 2 rad/s), c = 0.8 N·s/m (damping ratio
// 0.1, underdamped), x(0) = 1 m, v(0) = 0, over t in [0, 10] s.
struct DampedParticle {
  static constexpr LinearParticle kParticle{2.0, 8.0, 0.8};
  static constexpr double kX0_m = 1.0;
  static constexpr double kV0_m_per_s = 0.0;
  static constexpr double kTEnd_s = 10.0;
  static constexpr double kSteps_s[3] = {0.02, 0.1, 0.4};
  static constexpr double kReferenceStep_s = 1e-4;  // the paper's RK4 reference

  // Closed form (x [m], v [m/s]) of the underdamped oscillator at t.
  static std::pair<double, double> Exact(double t_s, const LinearParticle& p = kParticle,
                                         double x0 = kX0_m, double v0 = kV0_m_per_s) {
    const double g = p.c_Ns_per_m / (2.0 * p.m_kg);
    const double wd = std::sqrt(p.k_N_per_m / p.m_kg - g * g);
    const double a = x0, b = (v0 + g * x0) / wd;
    const double e = pmath::Exp(-g * t_s), cs = pmath::Cos(wd * t_s), sn = pmath::Sin(wd * t_s);
    return {e * (a * cs + b * sn), e * ((wd * b - g * a) * cs - (g * b + wd * a) * sn)};
  }
};

}  // namespace hapsim::core::paper
