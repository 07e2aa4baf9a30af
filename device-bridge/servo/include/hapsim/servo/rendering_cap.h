// Caps what a force model asks the device to render, applied when the
// servo takes a model: a spring stiffer or a damper stronger than the
// device renders stably makes it buzz or kick, whatever the force clamp
// says. Every stiffness (normal or lateral, stick, tip) is capped at
// max_stiffness and every damping (normal or axial, drag) at max_damping;
// anchors, directions and feed-forward stay, so the contact keeps its
// geometry and only feels softer. A NaN parameter is left as it is for the
// chain's non-finite stage. Pure and allocation-free.
#pragma once

#include "hapsim/core/haptics/local_force_model.h"

namespace hapsim::bridge {

// Returns true when anything was lowered.
bool CapRendering(core::LocalForceModel* model, double max_stiffness_N_per_m, double max_damping_Ns_per_m);

}  // namespace hapsim::bridge
