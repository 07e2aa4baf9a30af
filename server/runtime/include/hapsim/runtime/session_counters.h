// A session's counters, grouped by the one thread that writes each group, so
// a reader knows where a number comes from and the writers never share a
// cache line (the tick, the DDS thread and the frame pump run on different
// cores). Any thread may read them (gRPC handlers, /metrics, logs).
#pragma once
#include <atomic>
#include <cstdint>

#include "hapsim/runtime/tick_histogram.h"

namespace hapsim::service {

// Written by the session's tick (one pool worker at a time).
struct alignas(64) TickCounters {
  std::atomic<std::uint64_t> ticks{0};
  std::atomic<std::uint64_t> late_ticks{0};            // started > one period after due
  std::atomic<std::uint64_t> tick_work_ns{0};          // wall time from tick start to the scene stepped, summed
  std::atomic<std::uint64_t> device_clocked_ticks{0};  // run because a pose arrived
  std::atomic<std::int64_t> max_lateness_ns{0};
  std::atomic<std::uint64_t> force_models_sent{0};
  std::atomic<std::uint64_t> force_models_held{0};  // not sent: the device would not feel the change (ModelDeadband)
  // Poses of the owning device's sequence no tick used: lost, overwritten by
  // a newer one before it was read, or superseded in the mailbox when several
  // arrived at once (a tick takes the newest), or never sent (the bridge's
  // pose deadband). The thinning that jitter causes.
  std::atomic<std::uint64_t> poses_unused{0};
  std::atomic<std::uint64_t> snapshots_skipped{0};  // every ring buffer was still being read
  std::atomic<std::uint64_t> numerical_resets{0};
  std::atomic<std::uint32_t> owning_device_id{0};
  std::atomic<bool> device_streaming{false};
  std::atomic<double> sim_time_s{0.0};
  std::atomic<double> peak_tool_force_N{0.0};
  TickHistogram tick_work;      // a tick's wall time up to the scene stepped
  TickHistogram tick_lateness;  // how long after its due time a tick started
  TickHistogram pose_to_model;  // a fresh pose's arrival to its model's t_server_ns
};

// Written by the DDS I/O thread as it routes the session's poses.
struct alignas(64) PoseCounters {
  std::atomic<std::uint64_t> received{0};            // accepted and put in the session's mailbox
  std::atomic<std::uint64_t> rejected{0};            // malformed
  std::atomic<std::uint64_t> from_other_devices{0};  // another device owns the session
  std::atomic<std::uint64_t> stale{0};               // from the owner, seq not above the last accepted
  std::atomic<std::uint64_t> wrong_session{0};       // in this partition but naming another session
};

// Written by the ViewerHub (frame pump and stream threads).
struct alignas(64) ViewerCounters {
  std::atomic<std::uint32_t> connected{0};         // viewer streams subscribed now
  std::atomic<std::uint64_t> frames_coalesced{0};  // a viewer's previous frame or ack window was outstanding
  std::atomic<std::uint64_t> frames_sent{0};       // frames written to all its viewers
  std::atomic<std::uint64_t> bytes_sent{0};        // their encoded size
};

struct SessionCounters {
  TickCounters tick;
  PoseCounters poses;
  ViewerCounters viewers;
};

}  // namespace hapsim::service
