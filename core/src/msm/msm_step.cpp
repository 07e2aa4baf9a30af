// StepMsm / StepMsmLocal: dispatch to the scheme (explicit_schemes.h,
// backward_euler.h), each written once and templated on the node/spring
// index ranges (step_common.h): DenseRange for the full update (dense loops)
// and ListRange for the local update region; then the stability guard.
//
// Memory traffic is what limits a step on large meshes, so each force
// evaluation is one pass over the springs (scatter into the accumulator f)
// plus the integrator's own pass over the nodes, which adds the per-node
// force terms, updates x and v, resets f and accumulates the stability
// guard — nothing else touches the node arrays.
#include "hapsim/core/msm/msm_step.h"

#include <algorithm>
#include <cmath>

#include "backward_euler.h"
#include "explicit_schemes.h"
#include "flush_denormals.h"
#include "step_common.h"

namespace hapsim::core {

using detail::DenseRange;
using detail::ListRange;
using detail::Ranges;

MsmWorkspace MakeMsmWorkspace(const MsmModel& model) {
  MsmWorkspace ws;
  const Eigen::Index n = model.num_nodes;
  ws.f.assign(kSpringForceStride * static_cast<std::size_t>(n), 0.0);  // must start at zero (msm_kernels.h)
  for (Eigen::Matrix3Xd* m : {&ws.xs, &ws.vs, &ws.sum_x, &ws.sum_v, &ws.rhs,
                              &ws.dv, &ws.r, &ws.p, &ws.ap})
    *m = Eigen::Matrix3Xd::Zero(3, n);
  ws.spring_u.assign(3 * static_cast<std::size_t>(model.spring_capacity), 0.0);
  ws.spring_geo.assign(static_cast<std::size_t>(model.spring_capacity), 0.0);
  return ws;
}

namespace {

template <class R>
StepReport StepWith(const MsmModel& m, MsmState& s, double h, IntegratorChoice method, MsmWorkspace& ws, R r) {
  const detail::ScopedFlushDenormals flush_denormals;  // a relaxing tissue would run 3x slower
  StepReport report;
  detail::Guard g;
  switch (method.kind) {
    case IntegratorKind::kExplicitEuler: detail::ExplicitEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kSymplecticEuler: detail::SymplecticEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kImprovedEuler: detail::ImprovedEuler(m, s, h, ws, r, g); break;
    case IntegratorKind::kMidpointAveraging: detail::MidpointAveraging(m, s, h, method.alpha, ws, r, g); break;
    case IntegratorKind::kRk4: detail::Rk4(m, s, h, ws, r, g); break;
    case IntegratorKind::kBackwardEuler: report.cg_iterations = detail::BackwardEuler(m, s, h, ws, r, g); break;
  }
  // Keep the accumulator all-zero for a following full step.
  if constexpr (R::local) detail::ZeroAccumulator(ws.f.data(), r.touched);
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
  const DenseRange nodes{model.num_nodes};
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<DenseRange, DenseRange, false>{nodes, nodes, DenseRange{model.NumSprings()}});
}

StepReport StepMsmLocal(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method, MsmWorkspace& ws,
                        const LocalRegion& region, SpringPassListener* listener) {
  auto list = [](const std::vector<std::int32_t>& v) { return ListRange{v.data(), static_cast<std::int32_t>(v.size())}; };
  return StepWith(model, state, dt_s, method, ws,
                  Ranges<ListRange, ListRange, true>{list(region.active_nodes), list(region.touched_nodes),
                                                     list(region.springs), listener});
}

}  // namespace hapsim::core
