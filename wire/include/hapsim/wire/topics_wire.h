// The bodies of the two DDS topics to and from core types. The headers
// (device and session ids, sequence numbers, clocks, the server instance)
// are the endpoints' own and set by them; these functions carry what the
// physics and the device exchange.
#pragma once
#include <Eigen/Core>

#include "hapsim/core/haptics/local_force_model.h"
#include "hapsim/core/scenes/scene.h"
#include "haptics.h"  // hapsim_dds_StylusPose, hapsim_dds_LocalForceModel (idlc-generated)

namespace hapsim::wire {

// The model the device renders and the physics' own tool force [N].
void PackForceModel(const core::LocalForceModel& model, const Eigen::Vector3d& tool_force_W_N,
                    hapsim_dds_LocalForceModel* out);
// A state above 3 (unknown) reads as free: feed-forward only.
core::LocalForceModel UnpackForceModel(const hapsim_dds_LocalForceModel& in);
Eigen::Vector3d UnpackToolForce_W_N(const hapsim_dds_LocalForceModel& in);

// The tool's pose: tip [m], orientation, velocity [m/s], buttons. `valid` is
// not on the wire (a pose that arrives is a tool that is there).
void PackPose(const core::ToolInput& tool, hapsim_dds_StylusPose* out);
// Unchecked: the server filters a pose (FilterPose) before it may reach a
// scene; the orientation comes back as sent, not normalised.
core::ToolInput UnpackPose(const hapsim_dds_StylusPose& in);

}  // namespace hapsim::wire
