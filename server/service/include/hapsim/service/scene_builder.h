// Builds a scene off the real-time path: on a short-lived thread at low CPU
// priority (nice 10), so that while a large scene is built, the
// tick workers on the same core still run when they are due (the kernel
// preempts the builder for them). The caller waits for the result.
#pragma once
#include <memory>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

// Throws what core::MakeScene throws (std::invalid_argument on bad input).
std::unique_ptr<core::Scene> BuildSceneAtLowPriority(const core::SceneSpec& spec);

}  // namespace hapsim::service
