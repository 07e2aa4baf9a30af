// Internal: backward Euler, one Baraff-Witkin linearised step
// (M - h C - h^2 K) dv = h (f + h K v), solved by conjugate gradients with
// the geometric stiffness clamped at >= 0 so the system is SPD. Included
// only by msm_step.cpp.
#pragma once
#include <algorithm>
#include <cmath>

#include "hapsim/core/msm/msm_step.h"
#include "step_common.h"

namespace hapsim::core::detail {

// Per spring: unit direction and clamped geometric factor at the step start.
template <class R>
void LinearizeSprings(const MsmModel& m, const double* x, MsmWorkspace& ws, R r) {
  double* __restrict u = ws.spring_u.data();
  double* __restrict geo = ws.spring_geo.data();
  for (std::int32_t k = 0; k < r.springs.size(); ++k) {
    const std::int32_t s = r.springs[k];
    const auto us = static_cast<std::size_t>(s);
    const std::int32_t i = m.spring_i[us], j = m.spring_j[us];
    double d[3];
    for (int c = 0; c < 3; ++c) d[c] = x[3 * j + c] - x[3 * i + c];
    const double inv_l = 1.0 / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + detail::kTinyLength2_m2);
    for (int c = 0; c < 3; ++c) u[3 * s + c] = d[c] * inv_l;
    geo[s] = std::max(0.0, 1.0 - m.spring_rest_m[us] * inv_l);
  }
}

// out = (cm M + cc C + ck Kop) in over the touched nodes, where Kop = -df/dx
// (springs with clamped geometric term, anchors) and C = -df/dv (absolute
// and spring-axial dampers).
template <class R>
void ApplySystem(const MsmModel& m, const MsmWorkspace& ws, double cm, double cc, double ck, const double* in,
                 double* out, R r) {
  const double* u = ws.spring_u.data();
  const double* geo = ws.spring_geo.data();
  for (std::int32_t k = 0; k < r.touched.size(); ++k) {
    const std::int32_t i = r.touched[k];
    const double diag = cm * m.mass_kg[i] + cc * m.absolute_damping_Ns_per_m[i] + ck * m.anchor_k_sum_N_per_m[i];
    for (int c = 0; c < 3; ++c) out[3 * i + c] = diag * in[3 * i + c];
  }
  for (std::int32_t k = 0; k < r.springs.size(); ++k) {
    const auto s = static_cast<std::size_t>(r.springs[k]);
    const std::int32_t i = m.spring_i[s], j = m.spring_j[s];
    double w[3];
    for (int c = 0; c < 3; ++c) w[c] = in[3 * i + c] - in[3 * j + c];
    const double uw = u[3 * s] * w[0] + u[3 * s + 1] * w[1] + u[3 * s + 2] * w[2];
    const double kk = ck * m.spring_k_N_per_m[s];
    const double axial = (cc * m.spring_c_Ns_per_m[s] + kk * (1.0 - geo[s])) * uw;
    for (int c = 0; c < 3; ++c) {
      const double t = axial * u[3 * s + c] + kk * geo[s] * w[c];
      out[3 * i + c] += t;
      out[3 * j + c] -= t;
    }
  }
}

// Dot product over the free active nodes (fixed nodes are filtered out).
template <class R>
double DotActive(const MsmModel& m, const double* a, const double* b, R r) {
  double sum = 0.0;
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    const double free = m.fixed[static_cast<std::size_t>(i)] ? 0.0 : 1.0;
    sum += free * (a[3 * i] * b[3 * i] + a[3 * i + 1] * b[3 * i + 1] + a[3 * i + 2] * b[3 * i + 2]);
  }
  return sum;
}

template <class R>
int BackwardEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* x = s.x_m.data();
  double* v = s.v_m_per_s.data();
  double *f = ws.f.data(), *rhs = ws.rhs.data(), *dv = ws.dv.data(), *res = ws.r.data(), *p = ws.p.data(),
         *ap = ws.ap.data();
  const NodeTerms t(m, s);
  SpringPass(m, ws, x, v, r);
  LinearizeSprings(m, x, ws, r);
  // rhs = h f - h^2 Kop v  (= h (f + h K v), K = df/dx); filtered to free active nodes.
  ApplySystem(m, ws, 0.0, 0.0, h * h, v, rhs, r);
  if constexpr (R::local) {
    ZeroNodes(dv, r.touched);
    ZeroNodes(res, r.touched);
    ZeroNodes(p, r.touched);
  }
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    const double free = m.fixed[static_cast<std::size_t>(i)] ? 0.0 : 1.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      res[e] = free * (h * t.Take(f, x, v, i, c) - rhs[e]);
      p[e] = res[e];
      dv[e] = 0.0;
    }
  }
  // Conjugate gradients on (M + h C + h^2 Kop) dv = rhs (SPD: Kop clamped).
  double rr = DotActive(m, res, res, r);
  if (!std::isfinite(rr)) {  // NaN/inf force: let it reach the state so the guard sees it
    for (std::int32_t k = 0; k < r.active.size(); ++k)
      for (int c = 0; c < 3; ++c) dv[3 * r.active[k] + c] = rr;
  }
  const double tol2 = ws.cg_relative_tolerance * ws.cg_relative_tolerance * rr;
  int it = 0;
  while (it < ws.cg_max_iterations && rr > tol2 && rr > 0.0) {
    ApplySystem(m, ws, 1.0, h, h * h, p, ap, r);
    const double pap = DotActive(m, p, ap, r);
    if (!(pap > 0.0)) break;
    const double step = rr / pap;
    for (std::int32_t k = 0; k < r.active.size(); ++k) {
      const std::int32_t i = r.active[k];
      const double free = m.fixed[static_cast<std::size_t>(i)] ? 0.0 : 1.0;
      for (int c = 0; c < 3; ++c) {
        dv[3 * i + c] += step * p[3 * i + c];
        res[3 * i + c] -= free * step * ap[3 * i + c];
      }
    }
    const double rr_new = DotActive(m, res, res, r);
    const double beta = rr_new / rr;
    for (std::int32_t k = 0; k < r.active.size(); ++k)
      for (int c = 0; c < 3; ++c) p[3 * r.active[k] + c] = res[3 * r.active[k] + c] + beta * p[3 * r.active[k] + c];
    rr = rr_new;
    ++it;
  }
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      v[e] += dv[e];
      x[e] += h * v[e];
      g.position_sum += x[e];
      v2 += v[e] * v[e];
    }
    g.mass_v2 += m.mass_kg[i] * v2;
  }
  return it;
}

}  // namespace hapsim::core::detail
