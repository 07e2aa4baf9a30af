// One step of each integrator for a single degree of freedom, written out
// exactly as in integrator_kind.h. Used by the validation problems, by the
// critical-time-step estimate (amplification matrix of a mode) and by tests
// as the scalar reference the MSM step must agree with.
#pragma once
#include <cmath>

#include "hapsim/core/msm/integrator_kind.h"

namespace hapsim::core {

// Linear damped oscillator m x'' = -k x - c x': a(x, v) = -(k x + c v) / m.
struct LinearParticle {
  double m_kg = 1.0;
  double k_N_per_m = 1.0;
  double c_Ns_per_m = 0.0;
  double Accel(double x, double v) const { return -(k_N_per_m * x + c_Ns_per_m * v) / m_kg; }
};

// Second-order step for a(x, v) = p.Accel(x, v).
inline void StepParticle(const LinearParticle& p, IntegratorChoice m, double h, double& x,
                         double& v) {
  switch (m.kind) {
    case IntegratorKind::kExplicitEuler: {
      const double a = p.Accel(x, v);
      x += h * v;
      v += h * a;
      return;
    }
    case IntegratorKind::kSymplecticEuler:
      v += h * p.Accel(x, v);
      x += h * v;
      return;
    case IntegratorKind::kImprovedEuler: {
      const double v1 = v + h * p.Accel(x, v);
      x += 0.5 * h * (v + v1);
      v = v1;
      return;
    }
    case IntegratorKind::kMidpointAveraging: {
      const double vs = v + m.alpha * h * p.Accel(x, v);
      const double xs = x + m.alpha * h * vs;
      const double v1 = v + h * p.Accel(xs, vs);
      x += 0.5 * h * (v + v1);
      v = v1;
      return;
    }
    case IntegratorKind::kRk4: {
      const double k1x = v, k1v = p.Accel(x, v);
      const double k2x = v + 0.5 * h * k1v, k2v = p.Accel(x + 0.5 * h * k1x, k2x);
      const double k3x = v + 0.5 * h * k2v, k3v = p.Accel(x + 0.5 * h * k2x, k3x);
      const double k4x = v + h * k3v, k4v = p.Accel(x + h * k3x, k4x);
      x += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
      return;
    }
    case IntegratorKind::kBackwardEuler: {
      // Linear: (m + h c + h^2 k) dv = h (f + h (-k) v), f = -k x - c v.
      const double f = -p.k_N_per_m * x - p.c_Ns_per_m * v;
      const double dv = h * (f - h * p.k_N_per_m * v) /
                        (p.m_kg + h * p.c_Ns_per_m + h * h * p.k_N_per_m);
      v += dv;
      x += h * v;
      return;
    }
  }
}

// First-order scalar ODE y' = f(t, y). The MSM schemes are defined on (x, v);
// here y plays the role of v (the quantity whose update differs between the
// schemes) and there is no position. Taking the definitions literally:
//   explicit Euler:       y' = y + h f(t, y)
//   improved Euler:       v-update is explicit Euler -> identical to it
//   midpoint-averaging a: y* = y + a h f(t, y); y' = y + h f(t + a h, y*)
//   RK4:                  classic
// plus Heun's method (the textbook "improved Euler"),
//   y* = y + h f(t, y); y' = y + h/2 (f(t, y) + f(t + h, y*)),
// which is what the a = 1/2 scheme coincides with when f is linear in y and
// in t (shown in tests/core/integrator_order_test.cpp).
enum class FirstOrderMethod { kExplicitEuler, kImprovedEuler, kHeun, kMidpointAveraging, kRk4 };

template <class F>
double StepFirstOrder(FirstOrderMethod method, double alpha, F&& f, double t, double y, double h) {
  switch (method) {
    case FirstOrderMethod::kExplicitEuler:
    case FirstOrderMethod::kImprovedEuler:
      return y + h * f(t, y);
    case FirstOrderMethod::kHeun: {
      const double f0 = f(t, y);
      return y + 0.5 * h * (f0 + f(t + h, y + h * f0));
    }
    case FirstOrderMethod::kMidpointAveraging:
      return y + h * f(t + alpha * h, y + alpha * h * f(t, y));
    case FirstOrderMethod::kRk4: {
      const double k1 = f(t, y);
      const double k2 = f(t + 0.5 * h, y + 0.5 * h * k1);
      const double k3 = f(t + 0.5 * h, y + 0.5 * h * k2);
      const double k4 = f(t + h, y + h * k3);
      return y + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
  }
  return y;
}

}  // namespace hapsim::core
