// The checks every pose sample taken from a session's DDS partition goes
// through, in order, and what each refusal counts:
//   FilterPose (non-finite, out of range, bad session field)  -> poses_rejected
//   the sample names another session than the partition's    -> poses_wrong_session
//   another device owns the session                           -> poses_other_device
//   not newer than the owner's last accepted seq               -> poses_stale
//   otherwise the pose is offered to the session             -> poses_accepted
// (the per-session counters are kept by the session and here). Pure of DDS,
// so the routing is unit-tested and fuzzed without a reader
// (tests/fuzz/fuzz_pose_routing.cpp); ServerDds calls it with each batch it takes.
#pragma once
#include <cstdint>
#include <span>

#include "hapsim/device_link/pose_filter.h"
#include "hapsim/device_link/server_dds.h"
#include "hapsim/device_link/warning_limiter.h"
#include "hapsim/runtime/session.h"

namespace hapsim::service {

// Routes one batch into `session`; true if at least one pose was offered
// (the caller then wakes the session at session.PoseDueNs(now_ns)).
bool RoutePoseBatch(Session& session, std::span<const hapsim_dds_StylusPose> batch, const PoseLimits& limits,
                    std::int64_t now_ns, ServerDdsCounters* counters, WarningLimiter* warnings);

}  // namespace hapsim::service
