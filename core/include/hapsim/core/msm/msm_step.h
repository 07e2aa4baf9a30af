// Advancing an MSM by one time step with a chosen integrator.
//
//   MsmWorkspace ws = MakeMsmWorkspace(model);        // allocates, once
//   StepReport r = StepMsm(model, state, dt, choice, ws);   // never allocates
//
// The stability guard runs at the end of every step: non-finite positions or
// velocities, or kinetic energy above model.max_kinetic_energy_J, mark the
// step as a blow-up, count it in state.blowups and return ok = false. The
// state is then left as computed; the caller (a scene) resets it.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/aligned_allocator.h"
#include "hapsim/core/msm/local_region.h"
#include "hapsim/core/msm/msm_model.h"
#include "hapsim/core/msm/msm_state.h"
#include "hapsim/core/msm/spring_kernel.h"

namespace hapsim::core {

// Scratch memory for every integrator, sized from the model's node count and
// spring capacity so cutting (AddSpring within capacity) never invalidates it.
struct MsmWorkspace {
  // Spring-force accumulator [N], kSpringForceStride (4) doubles per node:
  // x, y, z and a pad lane (never read), so one node's force is one aligned
  // 32-byte vector. All zero between steps.
  std::vector<double, AlignedAllocator<double, 64>> f;
  Eigen::Matrix3Xd xs, vs;        // stage state (3 x n)
  Eigen::Matrix3Xd sum_x, sum_v;  // RK4 weighted stage sums (3 x n)
  // Backward Euler / CG (3 x n each).
  Eigen::Matrix3Xd rhs, dv, r, p, ap;
  std::vector<double> spring_u;    // unit direction per spring (3 x capacity)
  std::vector<double> spring_geo;  // clamped k (1 - L0/l) per spring (capacity)
  // Spring-force kernel; any supported choice gives bit-identical results.
  // An unsupported choice falls back to kPortable.
  SpringKernel spring_kernel = BestSpringKernel();
  // Implicit solver controls.
  int cg_max_iterations = 200;
  double cg_relative_tolerance = 1e-10;
};

MsmWorkspace MakeMsmWorkspace(const MsmModel& model);

struct StepReport {
  bool ok = true;                 // false: blow-up detected (counted in state.blowups)
  bool non_finite = false;        // NaN/inf in x or v
  bool energy_exceeded = false;   // kinetic energy > model.max_kinetic_energy_J
  double kinetic_energy_J = 0.0;  // after the step
  int cg_iterations = 0;          // backward Euler only
};

// Full update: every free node is integrated.
StepReport StepMsm(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method,
                   MsmWorkspace& ws);

// Told by a local step of a scheme with one force evaluation (explicit or
// symplectic Euler) when its spring pass is done: the springs' forces on the
// region's frozen neighbours are then known, at the state the step starts
// from. It may append nodes to the region's active list, completing their
// accumulator entries with the forces of their springs outside the region;
// the node pass then integrates them. Returns the active list's length.
class SpringPassListener {
 public:
  // spring_forces_N: the accumulator, kSpringForceStride doubles per node.
  virtual std::int32_t AfterSpringPass(double* spring_forces_N) = 0;

 protected:
  ~SpringPassListener() = default;
};

// Local update (gingival paper): only region.active_nodes are integrated;
// every other node is frozen where it is. Forces come from the springs and
// anchors incident to active nodes only, so the cost scales with the region.
// A listener may only append to region's lists (their buffers reserved by
// MakeLocalRegion, so they do not move).
StepReport StepMsmLocal(const MsmModel& model, MsmState& state, double dt_s, IntegratorChoice method, MsmWorkspace& ws,
                        const LocalRegion& region, SpringPassListener* listener = nullptr);

}  // namespace hapsim::core
