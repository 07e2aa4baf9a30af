#include "hapsim/servo/rendering_cap.h"

namespace hapsim::bridge {

namespace {
// Lowers *value to cap if above it (NaN is not above anything).
bool LowerTo(double* value, double cap) {
  if (!(*value > cap)) return false;
  *value = cap;
  return true;
}
}  // namespace

bool CapRendering(core::LocalForceModel* m, double max_stiffness_N_per_m, double max_damping_Ns_per_m) {
  bool capped = LowerTo(&m->stiffness_N_per_m, max_stiffness_N_per_m);
  capped |= LowerTo(&m->stick_stiffness_N_per_m, max_stiffness_N_per_m);
  capped |= LowerTo(&m->tip_stiffness_N_per_m, max_stiffness_N_per_m);
  capped |= LowerTo(&m->release_stiffness_N_per_m, max_stiffness_N_per_m);
  capped |= LowerTo(&m->damping_Ns_per_m, max_damping_Ns_per_m);
  capped |= LowerTo(&m->drag_damping_Ns_per_m, max_damping_Ns_per_m);
  capped |= LowerTo(&m->release_damping_Ns_per_m, max_damping_Ns_per_m);
  return capped;
}

}  // namespace hapsim::bridge
