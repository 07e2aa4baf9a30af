// The integrators on the MSM. Every scheme is written once, templated on
// the node/spring/anchor index ranges: AllRange for the full update (dense
// loops the compiler vectorises) and ListRange for the local update region.
#include "hapsim/core/integrators/msm_step.h"

#include <algorithm>
#include <cmath>

#include "../msm/msm_kernels.h"

namespace hapsim::core {

using detail::AllRange;
using detail::ListRange;

MsmWorkspace MakeMsmWorkspace(const MsmModel& model) {
  MsmWorkspace ws;
  const Eigen::Index n = model.num_nodes;
  for (Eigen::Matrix3Xd* m : {&ws.f, &ws.x0, &ws.v0, &ws.xs, &ws.vs, &ws.sum_x, &ws.sum_v, &ws.rhs,
                              &ws.dv, &ws.r, &ws.p, &ws.ap})
    *m = Eigen::Matrix3Xd::Zero(3, n);
  ws.spring_u.assign(3 * static_cast<std::size_t>(model.spring_capacity), 0.0);
  ws.spring_geo.assign(static_cast<std::size_t>(model.spring_capacity), 0.0);
  return ws;
}

namespace {

// Index sets one step works on. Full update: active = touched = all nodes.
// Local update: active = integrated nodes; touched = active + frozen spring
// neighbours (their positions are read, their forces are scratch).
template <class Active, class Touched, class Springs, class Anchors, bool kLocal>
struct Ranges {
  Active active;
  Touched touched;
  Springs springs;
  Anchors anchors;
  static constexpr bool local = kLocal;
};

template <class R>
void Forces(const MsmModel& m, const MsmState& s, const double* x, const double* v, double* f, R r) {
  detail::NodeForces(m, s, v, f, r.touched);
  detail::SpringForces(m, x, v, f, r.springs);
  detail::AnchorForces(m, x, v, f, r.anchors);
}

// Stage buffers start as a copy of the frozen neighbours' state (local only:
// in the full update every node is written by the stage itself).
template <class R>
void CopyTouched(const double* x, const double* v, double* xs, double* vs, R r) {
  if constexpr (R::local) {
    for (std::int32_t k = 0; k < r.touched.size(); ++k) {
      const std::int32_t i = r.touched[k];
      for (int c = 0; c < 3; ++c) {
        xs[3 * i + c] = x[3 * i + c];
        vs[3 * i + c] = v[3 * i + c];
      }
    }
  }
}

// Calls body(e, inv_m) for every scalar entry e = 3 i + c of the active nodes.
template <class Nodes, class Body>
inline void ForActive(const MsmModel& m, Nodes nodes, Body&& body) {
  const double* __restrict inv_m = m.inv_mass_free_per_kg.data();
  for (std::int32_t k = 0; k < nodes.size(); ++k) {
    const std::int32_t i = nodes[k];
    const double w = inv_m[i];
    body(3 * i + 0, w);
    body(3 * i + 1, w);
    body(3 * i + 2, w);
  }
}

template <class R>
void ExplicitEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  Forces(m, s, x, v, f, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    x[e] += h * v[e];
    v[e] += h * w * f[e];
  });
}

template <class R>
void SymplecticEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  Forces(m, s, x, v, f, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    v[e] += h * w * f[e];
    x[e] += h * v[e];
  });
}

template <class R>
void ImprovedEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  Forces(m, s, x, v, f, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    const double v1 = v[e] + h * w * f[e];
    x[e] += 0.5 * h * (v[e] + v1);
    v[e] = v1;
  });
}

template <class R>
void MidpointAveraging(const MsmModel& m, MsmState& s, double h, double alpha, MsmWorkspace& ws, R r) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  double* __restrict xs = ws.xs.data();
  double* __restrict vs = ws.vs.data();
  const double ah = alpha * h;
  Forces(m, s, x, v, f, r);
  CopyTouched(x, v, xs, vs, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    vs[e] = v[e] + ah * w * f[e];
    xs[e] = x[e] + ah * vs[e];
  });
  Forces(m, s, xs, vs, f, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    const double v1 = v[e] + h * w * f[e];
    x[e] += 0.5 * h * (v[e] + v1);
    v[e] = v1;
  });
}

template <class R>
void Rk4(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  double* __restrict xs = ws.xs.data();
  double* __restrict vs = ws.vs.data();
  double* __restrict sx = ws.sum_x.data();
  double* __restrict sv = ws.sum_v.data();
  Forces(m, s, x, v, f, r);
  CopyTouched(x, v, xs, vs, r);
  ForActive(m, r.active, [&](std::int32_t e, double w) {  // k1 = (v, a)
    const double a = w * f[e];
    sx[e] = v[e];
    sv[e] = a;
    xs[e] = x[e] + 0.5 * h * v[e];
    vs[e] = v[e] + 0.5 * h * a;
  });
  for (const double stage_h : {0.5 * h, h}) {  // k2, k3
    Forces(m, s, xs, vs, f, r);
    ForActive(m, r.active, [&](std::int32_t e, double w) {
      const double kx = vs[e], kv = w * f[e];
      sx[e] += 2.0 * kx;
      sv[e] += 2.0 * kv;
      xs[e] = x[e] + stage_h * kx;
      vs[e] = v[e] + stage_h * kv;
    });
  }
  Forces(m, s, xs, vs, f, r);  // k4
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    x[e] += h / 6.0 * (sx[e] + vs[e]);
    v[e] += h / 6.0 * (sv[e] + w * f[e]);
  });
}

// --- Backward Euler (Baraff-Witkin) -------------------------------------

// Per spring: unit direction and clamped geometric factor at the step start.
template <class R>
void LinearizeSprings(const MsmModel& m, const double* x, MsmWorkspace& ws, R r) {
  double* __restrict u = ws.spring_u.data();
  double* __restrict geo = ws.spring_geo.data();
  for (std::int32_t k = 0; k < r.springs.size(); ++k) {
    const std::int32_t s = r.springs[k];
    const std::int32_t i = m.spring_i[static_cast<std::size_t>(s)], j = m.spring_j[static_cast<std::size_t>(s)];
    double d[3];
    for (int c = 0; c < 3; ++c) d[c] = x[3 * j + c] - x[3 * i + c];
    const double inv_l = 1.0 / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + detail::kTinyLength2_m2);
    for (int c = 0; c < 3; ++c) u[3 * s + c] = d[c] * inv_l;
    geo[s] = std::max(0.0, 1.0 - m.spring_rest_m[static_cast<std::size_t>(s)] * inv_l);
  }
}

// out = (cm M + cc C + ck Kop) in over the touched nodes, where Kop = -df/dx
// (springs with clamped geometric term, anchors) and C = -df/dv (node,
// spring-axial and anchor dampers).
template <class R>
void ApplySystem(const MsmModel& m, const MsmWorkspace& ws, double cm, double cc, double ck,
                 const double* in, double* out, R r) {
  const double* u = ws.spring_u.data();
  const double* geo = ws.spring_geo.data();
  for (std::int32_t k = 0; k < r.touched.size(); ++k) {
    const std::int32_t i = r.touched[k];
    const double diag = cm * m.mass_kg[i] + cc * m.node_damping_Ns_per_m[i];
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
  for (std::int32_t k = 0; k < r.anchors.size(); ++k) {
    const auto a = static_cast<std::size_t>(r.anchors[k]);
    const std::int32_t i = m.anchor_node[a];
    const double d = cc * m.anchor_c_Ns_per_m[a] + ck * m.anchor_k_N_per_m[a];
    for (int c = 0; c < 3; ++c) out[3 * i + c] += d * in[3 * i + c];
  }
}

template <class R>
double DotActive(const MsmModel& m, const double* a, const double* b, R r) {
  double sum = 0.0;
  ForActive(m, r.active, [&](std::int32_t e, double w) { sum += (w > 0.0 ? 1.0 : 0.0) * a[e] * b[e]; });
  return sum;
}

template <class R>
int BackwardEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r) {
  double* x = s.x_m.data();
  double* v = s.v_m_per_s.data();
  double *f = ws.f.data(), *rhs = ws.rhs.data(), *dv = ws.dv.data(), *res = ws.r.data(),
         *p = ws.p.data(), *ap = ws.ap.data();
  Forces(m, s, x, v, f, r);
  LinearizeSprings(m, x, ws, r);
  // rhs = h f - h^2 Kop v  (= h (f + h K v), K = df/dx); filtered to free active nodes.
  ApplySystem(m, ws, 0.0, 0.0, h * h, v, rhs, r);
  for (std::int32_t k = 0; k < r.touched.size(); ++k) {
    const std::int32_t i = r.touched[k];
    for (int c = 0; c < 3; ++c) {
      dv[3 * i + c] = 0.0;
      res[3 * i + c] = 0.0;
      p[3 * i + c] = 0.0;
    }
  }
  ForActive(m, r.active, [&](std::int32_t e, double w) {
    const double free = w > 0.0 ? 1.0 : 0.0;
    res[e] = free * (h * f[e] - rhs[e]);
    p[e] = res[e];
  });
  // Conjugate gradients on (M + h C + h^2 Kop) dv = rhs (SPD: Kop clamped).
  double rr = DotActive(m, res, res, r);
  if (!std::isfinite(rr)) {  // NaN/inf force: let it reach the state so the guard sees it
    ForActive(m, r.active, [&](std::int32_t e, double) { dv[e] = rr; });
  }
  const double tol2 = ws.cg_relative_tolerance * ws.cg_relative_tolerance * rr;
  int it = 0;
  while (it < ws.cg_max_iterations && rr > tol2 && rr > 0.0) {
    ApplySystem(m, ws, 1.0, h, h * h, p, ap, r);
    const double pap = DotActive(m, p, ap, r);
    if (!(pap > 0.0)) break;
    const double step = rr / pap;
    ForActive(m, r.active, [&](std::int32_t e, double w) {
      const double free = w > 0.0 ? 1.0 : 0.0;
      dv[e] += step * p[e];
      res[e] -= free * step * ap[e];
    });
    const double rr_new = DotActive(m, res, res, r);
    const double beta = rr_new / rr;
    ForActive(m, r.active, [&](std::int32_t e, double) { p[e] = res[e] + beta * p[e]; });
    rr = rr_new;
    ++it;
  }
  ForActive(m, r.active, [&](std::int32_t e, double) {
    v[e] += dv[e];
    x[e] += h * v[e];
  });
  return it;
}

template <class R>
StepReport StepWith(const MsmModel& m, MsmState& s, double h, IntegratorChoice method,
                    MsmWorkspace& ws, R r) {
  StepReport report;
  switch (method.kind) {
    case IntegratorKind::kExplicitEuler: ExplicitEuler(m, s, h, ws, r); break;
    case IntegratorKind::kSymplecticEuler: SymplecticEuler(m, s, h, ws, r); break;
    case IntegratorKind::kImprovedEuler: ImprovedEuler(m, s, h, ws, r); break;
    case IntegratorKind::kMidpointAveraging: MidpointAveraging(m, s, h, method.alpha, ws, r); break;
    case IntegratorKind::kRk4: Rk4(m, s, h, ws, r); break;
    case IntegratorKind::kBackwardEuler: report.cg_iterations = BackwardEuler(m, s, h, ws, r); break;
  }
  s.t_s += h;
  // Stability guard: NaN/inf propagate into the sum; kinetic energy bound.
  const double* x = s.x_m.data();
  const double* v = s.v_m_per_s.data();
  const double* mass = m.mass_kg.data();
  double sum = 0.0, kinetic2 = 0.0;
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    const double v2 = v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2];
    sum += x[3 * i] + x[3 * i + 1] + x[3 * i + 2];
    kinetic2 += mass[i] * v2;
  }
  report.kinetic_energy_J = 0.5 * kinetic2;
  report.non_finite = !std::isfinite(sum) || !std::isfinite(kinetic2);
  report.energy_exceeded = !report.non_finite && report.kinetic_energy_J > m.max_kinetic_energy_J;
  report.ok = !report.non_finite && !report.energy_exceeded;
  if (!report.ok) ++s.blowups;
  return report;
}

}  // namespace

StepReport StepMsm(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method,
                   MsmWorkspace& ws) {
  const AllRange nodes{model.num_nodes};
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<AllRange, AllRange, AllRange, AllRange, false>{
                      nodes, nodes, AllRange{model.NumSprings()}, AllRange{model.NumAnchors()}});
}

StepReport StepMsmLocal(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method,
                        MsmWorkspace& ws, const LocalRegion& region) {
  auto list = [](const std::vector<std::int32_t>& v) {
    return ListRange{v.data(), static_cast<std::int32_t>(v.size())};
  };
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<ListRange, ListRange, ListRange, ListRange, true>{
                      list(region.active_nodes), list(region.touched_nodes), list(region.springs),
                      list(region.anchors)});
}

}  // namespace hapsim::core
