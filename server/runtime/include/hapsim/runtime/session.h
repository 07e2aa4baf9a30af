// A session: one scene, stepped one period per tick. The session is passive —
// it owns no thread. A TickPool worker calls RunTick() when the session is
// due: when its device's newest pose arrives (the device is the clock), or on
// its own deadline when no device streams or the next pose is late by more
// than the slack. Each tick assembles one TickInput, steps, writes the force
// model at once through the sink (no hand-off to another thread), and every
// 1/frame-rate publishes a snapshot for viewers from a preallocated ring.
//
// Threads:
//   DDS thread    OfferPose()      -> pose mailbox, device ownership
//   pool worker   RunTick()        (one at a time; never allocates)
//   frame pump    TakeSnapshot() (the ViewerHub fans snapshots out to viewers)
//   gRPC threads  RequestPause/Reset, counters
//
// The session knows neither gRPC nor DDS: force models leave as plain
// ForceModelMessages through its SessionPort (the DDS adapter packs them),
// and viewers are the ViewerHub's business.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/common/latest_value.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/runtime/device_ownership.h"
#include "hapsim/runtime/model_deadband.h"
#include "hapsim/runtime/scene_snapshot.h"
#include "hapsim/runtime/session_counters.h"
#include "hapsim/runtime/session_port.h"
#include "hapsim/runtime/snapshot_ring.h"
#include "hapsim/runtime/tick_input.h"
#include "hapsim/runtime/tick_input_source.h"
#include "hapsim/runtime/tick_listener.h"
#include "hapsim/runtime/tick_pool.h"

namespace hapsim::service {

struct SessionConfig {
  std::string id;
  std::string scene = "tissue_block";
  std::string owner;
  std::map<std::string, double> params;
  double tick_period_s = 0.001;      // physics tick (1 kHz)
  double frame_rate_hz = 60.0;       // snapshots for viewers
  double pose_timeout_s = 0.25;      // no pose for this long: the tool is absent
  // A streaming device's next pose may be this late before the session ticks
  // on its own deadline instead (with the previous pose).
  double pose_slack_s = 0.0005;
  // Between poses (a device that sends only when its pose leaves a deadband,
  // or a late one) the tool is extrapolated along its last velocity for at
  // most this long, then held (0: always held).
  double pose_extrapolation_s = 0.1;
  // Force models go out when the device would feel a change (ModelDeadband;
  // jnd 0: every tick).
  ModelDeadbandConfig model_deadband;
  // Where the tick count starts, and whether the tissue starts frozen: a
  // session restored after a server restart goes on from its recording.
  std::uint64_t first_tick = 0;
  bool start_paused = false;
  // Sim time each tick steps [s]; 0: the tick period. A replay at speed k
  // ticks every step_s / k.
  double step_s = 0.0;
};

// A pose accepted by the DDS thread.
struct PoseSample {
  core::ToolInput tool;
  std::uint32_t device_id = 0;
  std::uint64_t seq = 0;
  std::int64_t received_ns = 0;  // server steady clock
};

class Session : public TickTask {
 public:
  // Takes a scene already built (outside every lock; see SessionRegistry)
  // and the port its force models go out through (written on the worker,
  // right after the step), and optionally what follows its ticks. Throws
  // std::invalid_argument on a bad tick period or frame rate.
  // With a source, the ticks take their inputs from it (a replay), not
  // from a device: poses offered are ignored and no force model goes out.
  Session(SessionConfig config, std::unique_ptr<core::Scene> scene, std::shared_ptr<SessionPort> port,
          std::shared_ptr<TickListener> listener = nullptr, std::shared_ptr<TickInputSource> source = nullptr);
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  const SessionConfig& config() const { return config_; }
  const std::string& id() const { return config_.id; }
  SessionCounters& counters() { return counters_; }
  const SessionCounters& counters() const { return counters_; }
  bool paused() const { return paused_.load(); }
  SessionPort& port() const { return *port_; }

  // DDS thread only. Offers a pose: false (and counted) if another device
  // owns the session. On true, wake the session at PoseDueNs().
  PoseVerdict OfferPose(const PoseSample& pose);
  // When a tick for a pose that arrived at arrival_ns may run: at once,
  // unless the previous tick took a pose too and started less than half a
  // period earlier (a device streaming faster than the tick rate must not
  // speed up sim time). After a deadline tick (the pose was late, or its
  // deadband held it back) the pose is answered at once, and the deadline
  // after it is set as if it had waited that half period (NextDueNs), so the
  // ticks keep their pace.
  std::int64_t PoseDueNs(std::int64_t arrival_ns) const;

  // Pool worker (TickTask). One tick: input, step, force model, snapshot;
  // returns the next deadline.
  std::int64_t RunTick(std::int64_t due_ns, std::int64_t now_ns) override;

  // Called with every TickInput before it is applied (on the worker; for
  // recording and tests). Set before the session is added to a pool.
  void SetTickObserver(std::function<void(const TickInput&)> observer) { tick_observer_ = std::move(observer); }
  const core::Scene& scene() const { return *scene_; }  // only while no tick runs

  // Frame pump only. After taking a snapshot's topology edits, the pump says
  // up to which version it has them, so later snapshots carry only newer ones.
  bool TakeSnapshot(std::shared_ptr<const SceneSnapshot>* out) { return snapshot_outbox_.TakeIfNew(out); }
  // What follows this session's ticks (nullptr: nothing); fixed at creation.
  TickListener* tick_listener() const { return listener_.get(); }
  TickInputSource* input_source() const { return source_.get(); }  // nullptr: a device drives it
  const std::vector<std::string>& layer_names() const { return *layer_names_; }
  void MarkTopologyTaken(std::uint64_t version) { topology_taken_.store(version, std::memory_order_release); }

  // Any thread. Snapshots carry the mesh while a viewer is connected and,
  // besides, until `until_ns` (steady clock): whoever wants a session's mesh
  // without a viewer stream (GetSnapshot) asks for it here, then takes a
  // snapshot that has it. Without either, the frame-rate mesh copy is skipped.
  void WantMeshUntil(std::int64_t until_ns);

  // Any thread.
  void RequestPause(bool pause) { paused_.store(pause); }
  void RequestReset() { reset_requests_.fetch_add(1); }

 private:
  // The soonest a pose tick may follow the last tick (PoseDueNs's guard).
  std::int64_t HalfPeriodAfterLastTickNs() const;
  TickInput AssembleInput(std::int64_t now_ns);
  TickInput AssembleReplayInput();
  // paced_ns: when the tick would have run had every pose tick waited half
  // a period after the previous tick (its due time, or later).
  std::int64_t NextDueNs(const TickInput& in, std::int64_t due_ns, std::int64_t paced_ns, std::int64_t now_ns) const;
  void RecordTiming(const TickInput& in, std::int64_t due_ns, std::int64_t now_ns, double tool_force_N);
  void PublishForceModel(const TickInput& in, const core::LocalForceModel& model, std::int64_t now_ns);
  void PublishSnapshot(const TickInput& in);

  SessionConfig config_;
  std::int64_t period_ns_;
  std::int64_t pose_timeout_ns_;
  std::int64_t pose_slack_ns_;
  std::int64_t pose_extrapolation_ns_;
  ModelDeadband model_deadband_;
  std::unique_ptr<core::Scene> scene_;
  std::shared_ptr<SessionPort> port_;
  std::function<void(const TickInput&)> tick_observer_;
  std::shared_ptr<TickListener> listener_;
  std::shared_ptr<TickInputSource> source_;
  double step_s_;
  SessionCounters counters_;

  // DDS thread state.
  DeviceOwnership ownership_;

  common::LatestValue<PoseSample> pose_inbox_;
  common::LatestValue<std::shared_ptr<const SceneSnapshot>> snapshot_outbox_;
  std::atomic<bool> paused_{false};
  std::atomic<std::uint32_t> reset_requests_{0};
  std::atomic<std::int64_t> last_tick_start_ns_{0};  // written by the tick, read by the DDS thread
  std::atomic<bool> last_tick_took_pose_{false};     // likewise: the last tick took a fresh pose

  // Tick state (one worker at a time; the pool orders successive ticks).
  PoseSample last_pose_;
  TickInput last_replayed_;  // a replay's last input (its tool stays shown while paused)
  bool have_pose_ = false;
  std::int64_t pose_taken_ns_ = 0;  // the tick that took last_pose_ fresh
  std::uint64_t tick_index_ = 0;
  std::uint64_t force_seq_ = 0;
  std::uint64_t snapshot_id_ = 0;
  std::uint32_t resets_seen_ = 0;
  std::uint64_t ticks_per_frame_ = 16;
  ForceModelMessage force_message_;
  // Peak |tool force| of the ticks since the last published snapshot, and
  // of the last intervals (SceneSnapshot::interval_peak_N): tick thread only.
  double interval_peak_N_ = 0.0;
  std::array<double, SceneSnapshot::kPeakIntervals> interval_peaks_N_{};
  SnapshotRing snapshots_;
  std::shared_ptr<const std::vector<std::string>> part_names_;   // fixed at build
  std::shared_ptr<const std::vector<std::string>> layer_names_;  // fixed at build
  // The topology version up to which the frame pump has taken the edits
  // (written by the pump, read by the tick): snapshots carry only newer ones.
  std::atomic<std::uint64_t> topology_taken_{0};
  std::atomic<std::int64_t> mesh_wanted_until_ns_{0};  // WantMeshUntil
};

}  // namespace hapsim::service
