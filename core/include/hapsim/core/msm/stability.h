// Explicit critical time step of an MSM for a given integrator.
//
// The linearised system per mode is x'' = -w^2 x - g x'. Bounds on the modes
// come from Gershgorin discs of M^-1/2 K M^-1/2 (stiffness: springs, anchors
// and extra per-node contact stiffness) and of M^-1/2 C M^-1/2 (damping:
// node, spring and anchor dampers), which bound every eigenvalue from above.
// The critical step is the largest h for which the integrator's 2x2
// amplification matrix (from particle_steppers.h) has spectral radius <= 1
// for every mode in [0, w_max^2] x [g_min, g_max] (sampled). Backward Euler
// is unconditionally stable (returns +inf). Conservative for springs near
// rest; large stretches/compressions change the geometric stiffness.
#pragma once
#include "hapsim/core/msm/integrator_kind.h"
#include "hapsim/core/msm/msm_model.h"

namespace hapsim::core {

struct ModeBounds {
  double omega2_max_per_s2 = 0.0;  // upper bound of w^2 [1/s^2]
  double gamma_min_per_s = 0.0;    // lower bound of the damping rate c/m [1/s]
  double gamma_max_per_s = 0.0;    // upper bound of the damping rate [1/s]
};

// extra_node_stiffness_N_per_m / extra_node_damping_Ns_per_m: what a scene
// adds per node outside the model (e.g. the contact penalty spring-damper),
// included in the bounds.
ModeBounds EstimateModeBounds(const MsmModel& model, double extra_node_stiffness_N_per_m = 0.0,
                              double extra_node_damping_Ns_per_m = 0.0);

// Largest stable step [s] for a linear damped mode set; +inf if unconditional.
double CriticalTimeStep_s(const ModeBounds& bounds, IntegratorChoice method);

// Spectral radius of one step of `method` on x'' = -w2 x - g x'.
double AmplificationRadius(IntegratorChoice method, double omega2_per_s2, double gamma_per_s,
                           double h_s);

}  // namespace hapsim::core
