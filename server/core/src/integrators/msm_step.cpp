// The integrators on the MSM. Every scheme is written once, templated on
// the node/spring index ranges: AllRange for the full update (dense loops)
// and ListRange for the local update region.
//
// Memory traffic is what limits a step on large meshes, so each force
// evaluation is one pass over the springs (scatter into the accumulator f)
// plus the integrator's own pass over the nodes, which adds the per-node
// force terms, updates x and v, resets f and accumulates the stability
// guard — nothing else touches the node arrays.
#include "hapsim/core/integrators/msm_step.h"

#include <algorithm>
#include <cmath>

#include "../msm/msm_kernels.h"

namespace hapsim::core {

using detail::AllRange;
using detail::ListRange;
using detail::NodeTerms;

MsmWorkspace MakeMsmWorkspace(const MsmModel& model) {
  MsmWorkspace ws;
  const Eigen::Index n = model.num_nodes;
  for (Eigen::Matrix3Xd* m : {&ws.f, &ws.xs, &ws.vs, &ws.sum_x, &ws.sum_v, &ws.rhs,
                              &ws.dv, &ws.r, &ws.p, &ws.ap})
    *m = Eigen::Matrix3Xd::Zero(3, n);  // f must start at zero (see msm_kernels.h)
  ws.spring_u.assign(3 * static_cast<std::size_t>(model.spring_capacity), 0.0);
  ws.spring_geo.assign(static_cast<std::size_t>(model.spring_capacity), 0.0);
  return ws;
}

namespace {

// Index sets one step works on. Full update: active = touched = all nodes.
// Local update: active = integrated nodes; touched = active + frozen spring
// neighbours (their positions are read, their force entries are scratch).
template <class Nodes, class Springs, bool kLocal>
struct Ranges {
  Nodes active;
  Nodes touched;
  Springs springs;
  static constexpr bool local = kLocal;
};

template <class Nodes>
void ZeroNodes(double* f, Nodes nodes) {
  for (std::int32_t k = 0; k < nodes.size(); ++k) {
    const std::int32_t i = nodes[k];
    f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0.0;
  }
}

// Spring forces at (x, v) into f. Full update: f is all zero here (every
// consumer resets what it reads). Local update: frozen neighbours' entries
// may be stale, so the touched set is cleared first.
template <class R>
void SpringPass(const MsmModel& m, const double* x, const double* v, double* f, R r) {
  if constexpr (R::local) ZeroNodes(f, r.touched);
  detail::SpringForces(m, x, v, f, r.springs);
}

// Stage buffers start as a copy of the frozen neighbours' state (local
// only: in the full update the stage loop writes every node).
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

// Stability guard accumulators, filled in each scheme's final node loop.
struct Guard {
  double position_sum = 0.0;  // NaN/inf anywhere propagates into it
  double mass_v2 = 0.0;       // sum m v^2 = 2 x kinetic energy
};

template <class R>
void ExplicitEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPass(m, x, v, f, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      const double a = t.inv_mass[i] * t.Take(f, x, v, i, c);
      x[e] += h * v[e];
      v[e] += h * a;
      g.position_sum += x[e];
      v2 += v[e] * v[e];
    }
    g.mass_v2 += t.mass[i] * v2;
  }
}

template <class R>
void SymplecticEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPass(m, x, v, f, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      v[e] += h * t.inv_mass[i] * t.Take(f, x, v, i, c);
      x[e] += h * v[e];
      g.position_sum += x[e];
      v2 += v[e] * v[e];
    }
    g.mass_v2 += t.mass[i] * v2;
  }
}

template <class R>
void ImprovedEuler(const MsmModel& m, MsmState& s, double h, MsmWorkspace& ws, R r, Guard& g) {
  double* __restrict x = s.x_m.data();
  double* __restrict v = s.v_m_per_s.data();
  double* __restrict f = ws.f.data();
  const NodeTerms t(m, s);
  SpringPass(m, x, v, f, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      const double v1 = v[e] + h * t.inv_mass[i] * t.Take(f, x, v, i, c);
      x[e] += 0.5 * h * (v[e] + v1);
      v[e] = v1;
      g.position_sum += x[e];
      v2 += v1 * v1;
    }
    g.mass_v2 += t.mass[i] * v2;
  }
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
  SpringPass(m, x, v, f, r);
  CopyTouched(x, v, xs, vs, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      vs[e] = v[e] + ah * t.inv_mass[i] * t.Take(f, x, v, i, c);
      xs[e] = x[e] + ah * vs[e];
    }
  }
  SpringPass(m, xs, vs, f, r);
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      const double v1 = v[e] + h * t.inv_mass[i] * t.Take(f, xs, vs, i, c);
      x[e] += 0.5 * h * (v[e] + v1);
      v[e] = v1;
      g.position_sum += x[e];
      v2 += v1 * v1;
    }
    g.mass_v2 += t.mass[i] * v2;
  }
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
  SpringPass(m, x, v, f, r);
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
    SpringPass(m, xs, vs, f, r);
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
  SpringPass(m, xs, vs, f, r);  // k4
  for (std::int32_t k = 0; k < r.active.size(); ++k) {
    const std::int32_t i = r.active[k];
    double v2 = 0.0;
    for (int c = 0; c < 3; ++c) {
      const std::int32_t e = 3 * i + c;
      const double a4 = t.inv_mass[i] * t.Take(f, xs, vs, i, c);
      x[e] += h / 6.0 * (sx[e] + vs[e]);
      v[e] += h / 6.0 * (sv[e] + a4);
      g.position_sum += x[e];
      v2 += v[e] * v[e];
    }
    g.mass_v2 += t.mass[i] * v2;
  }
}

// --- Backward Euler (Baraff-Witkin) -------------------------------------

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
  SpringPass(m, x, v, f, r);
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

template <class R>
StepReport StepWith(const MsmModel& m, MsmState& s, double h, IntegratorChoice method, MsmWorkspace& ws, R r) {
  StepReport report;
  Guard g;
  switch (method.kind) {
    case IntegratorKind::kExplicitEuler: ExplicitEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kSymplecticEuler: SymplecticEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kImprovedEuler: ImprovedEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kMidpointAveraging: MidpointAveraging(m, s, h, method.alpha, ws, r, g); break;
    case IntegratorKind::kRk4: Rk4(m, s, h, ws, r, g); break;
    case IntegratorKind::kBackwardEuler: report.cg_iterations = BackwardEuler(m, s, h, ws, r, g); break;
  }
  // Keep the accumulator all-zero for a following full step.
  if constexpr (R::local) ZeroNodes(ws.f.data(), r.touched);
  s.t_s += h;
  report.kinetic_energy_J = 0.5 * g.mass_v2;
  report.non_finite = !std::isfinite(g.position_sum) || !std::isfinite(g.mass_v2);
  report.energy_exceeded = !report.non_finite && report.kinetic_energy_J > m.max_kinetic_energy_J;
  report.ok = !report.non_finite && !report.energy_exceeded;
  if (!report.ok) ++s.blowups;
  return report;
}

}  // namespace

StepReport StepMsm(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method, MsmWorkspace& ws) {
  const AllRange nodes{model.num_nodes};
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<AllRange, AllRange, false>{nodes, nodes, AllRange{model.NumSprings()}});
}

StepReport StepMsmLocal(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method,
                        MsmWorkspace& ws, const LocalRegion& region) {
  auto list = [](const std::vector<std::int32_t>& v) { return ListRange{v.data(), static_cast<std::int32_t>(v.size())}; };
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<ListRange, ListRange, true>{list(region.active_nodes), list(region.touched_nodes),
                                                      list(region.springs)});
}

}  // namespace hapsim::core
