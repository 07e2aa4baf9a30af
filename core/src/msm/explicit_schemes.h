// Internal: the explicit schemes (definitions in integrator_kind.h), each a
// spring pass per force evaluation plus one fused pass over the nodes.
// Included only by msm_step.cpp.
#pragma once
#include "hapsim/core/msm/msm_step.h"
#include "node_pass_avx512.h"
#include "step_common.h"

namespace hapsim::core::detail {

// The last node pass every explicit scheme ends with: for each active node
// and axis, the total force at (xa, va) [N] goes to update(e, i, force_N),
// which writes x[e] and v[e] by the scheme's rule; then the stability guard
// accumulates the new state. One loop, so the schemes differ only in their
// update line.
template <class R, class Update>
inline void FinalNodePass(const NodeTerms& t, double* __restrict f, const double* xa, const double* va,
                          const double* x, const double* v, R r, Guard& g, Update update) {
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      update(e, i, t.Take(f, xa, va, i, c));
      g.position_sum += x[e];
      v2 += v[e] * v[e];
    }
    g.mass_v2 += t.mass[i] * v2;
  }
}

// v' = v + h a, x' = x + h/2 (v + v'): improved Euler's update, which is
// also midpoint-averaging's last stage (with the force taken at its midpoint).
inline auto TrapezoidUpdate(double* __restrict x, double* __restrict v, const NodeTerms& t, double h) {
  return [x, v, &t, h](std::int32_t e, std::int32_t i, double force_N) {
    const double v1 = v[e] + h * t.inv_mass[i] * force_N;
    x[e] += 0.5 * h * (v[e] + v1);
    v[e] = v1;
  };
}

// The one spring pass of explicit and symplectic Euler; then the local
// update's listener may add nodes to the active list.
template <class R>
void SpringPassThenListener(const MsmModel& m, MsmWorkspace& ws, const double* x, const double* v, R& r) {
  SpringPass(m, ws, x, v, r);
  if constexpr (R::local)
    if (r.listener != nullptr) r.active.n = r.listener->AfterSpringPass(ws.f.data());
}

template <class R>
void ExplicitEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPassThenListener(m, ws, x, v, r);
  FinalNodePass(t, f, x, v, x, v, r, g, [&](std::int32_t e, std::int32_t i, double force_N) {
    const double a = t.inv_mass[i] * force_N;
    x[e] += h * v[e];
    v[e] += h * a;
  });
}

template <class R>
void SymplecticEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPassThenListener(m, ws, x, v, r);
#if HAPSIM_MSM_AVX512_KERNEL
  if (UsesAvx512(ws)) return SymplecticNodePassAvx512(t, f, x, v, h, r, g);
#endif
  FinalNodePass(t, f, x, v, x, v, r, g, [&](std::int32_t e, std::int32_t i, double force_N) {
    v[e] += h * t.inv_mass[i] * force_N;
    x[e] += h * v[e];
  });
}

template <class R>
void ImprovedEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPass(m, ws, x, v, r);
  FinalNodePass(t, f, x, v, x, v, r, g, TrapezoidUpdate(x, v, t, h));
}

template <class R>
void MidpointAveraging(const MsmModel& m, MsmState& s, double h, double alpha, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  double* __restrict xs = ws.xs.data();
  double* __restrict vs = ws.vs.data();
  const NodeTerms t(m, s);
  const double ah = alpha * h;
  SpringPass(m, ws, x, v, r);
  CopyTouched(x, v, xs, vs, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      vs[e] = v[e] + ah * t.inv_mass[i] * t.Take(f, x, v, i, c);
      xs[e] = x[e] + ah * vs[e];
    }
  }
  SpringPass(m, ws, xs, vs, r);
  FinalNodePass(t, f, xs, vs, x, v, r, g, TrapezoidUpdate(x, v, t, h));
}

template <class R>
void Rk4(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  double* __restrict xs = ws.xs.data();
  double* __restrict vs = ws.vs.data();
  double* __restrict sx = ws.sum_x.data();
  double* __restrict sv = ws.sum_v.data();
  const NodeTerms t(m, s);
  SpringPass(m, ws, x, v, r);
  CopyTouched(x, v, xs, vs, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {  // k1 = (v, a(x, v))
    const std::int32_t i = r.active[k];
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      const double a = t.inv_mass[i] * t.Take(f, x, v, i, c);
      sx[e] = v[e];
      sv[e] = a;
      xs[e] = x[e] + 0.5 * h * v[e];
      vs[e] = v[e] + 0.5 * h * a;
    }
  }
  for (const double stage_h : {0.5 * h, h}) {  // k2, k3
    SpringPass(m, ws, xs, vs, r);
    for (std::int32_t k = 0; k < r.active.size(); ++k) {
      const std::int32_t i = r.active[k];
      for (int c = 0; c < 3; ++c) {
        const std::int32_t e = 3 * i + c;
        const double kx = vs[e], kv = t.inv_mass[i] * t.Take(f, xs, vs, i, c);
        sx[e] += 2.0 * kx;
        sv[e] += 2.0 * kv;
        xs[e] = x[e] + stage_h * kx;
        vs[e] = v[e] + stage_h * kv;
      }
    }
  }
  SpringPass(m, ws, xs, vs, r);  // k4
  FinalNodePass(t, f, xs, vs, x, v, r, g, [&](std::int32_t e, std::int32_t i, double force_N) {
    const double a4 = t.inv_mass[i] * force_N;
    x[e] += h / 6.0 * (sx[e] + vs[e]);
    v[e] += h / 6.0 * (sv[e] + a4);
  });
}

}  // namespace hapsim::core::detail
