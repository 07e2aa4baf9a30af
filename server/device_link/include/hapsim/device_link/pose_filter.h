// Checks a StylusPose from the wire before it may reach a scene: a bad pose
// (NaN/inf, absurd position or speed, non-unit quaternion) is dropped and
// counted, never stepped — a client's mistake must not crash or destabilise
// the physics.
#pragma once
#include <optional>
#include <string_view>

#include "hapsim/core/scenes/scene.h"
#include "haptics.h"  // hapsim_dds_StylusPose (idlc-generated)

namespace hapsim::service {

struct PoseLimits {
  double max_distance_m = 2.0;       // from the origin; the device workspace is ~0.2 m, 2 m is clearly bogus
  double max_speed_m_per_s = 10.0;   // hand motion stays well below this
  double quaternion_norm_tolerance = 0.05;  // |q| must be within 1 ± this (then normalised)
};

enum class PoseRejection { kNone, kNotFinite, kPositionOutOfRange, kSpeedOutOfRange, kBadQuaternion, kBadSession };
std::string_view ToString(PoseRejection r);

// Returns the tool input, or nullopt with *why set.
std::optional<core::ToolInput> FilterPose(const hapsim_dds_StylusPose& pose, const PoseLimits& limits,
                                          PoseRejection* why);

// The session id carried in a sample: the bytes up to the first NUL; empty
// if there is none within the 64-byte field (malformed).
std::string_view SessionIdOf(const char (&field)[64]);

}  // namespace hapsim::service
