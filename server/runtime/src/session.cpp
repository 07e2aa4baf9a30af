#include "hapsim/runtime/session.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapsim/common/clock.h"

namespace hapsim::service {

namespace {

template <class T>
void AtomicMax(std::atomic<T>& a, T v) {
  T cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

std::int64_t SecondsToNs(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

constexpr std::size_t kRecentEvents = 64;  // events carried by each snapshot

}  // namespace

Session::Session(SessionConfig config, std::unique_ptr<core::Scene> scene, std::shared_ptr<SessionPort> port,
                 std::shared_ptr<TickListener> listener, std::shared_ptr<TickInputSource> source)
    : config_(std::move(config)),
      period_ns_(SecondsToNs(config_.tick_period_s)),
      pose_timeout_ns_(SecondsToNs(config_.pose_timeout_s)),
      pose_slack_ns_(SecondsToNs(config_.pose_slack_s)),
      pose_extrapolation_ns_(SecondsToNs(config_.pose_extrapolation_s)),
      model_deadband_(config_.model_deadband),
      scene_(std::move(scene)),
      port_(std::move(port)),
      listener_(std::move(listener)),
      source_(std::move(source)),
      step_s_(config_.step_s > 0.0 ? config_.step_s : config_.tick_period_s),
      ownership_(pose_timeout_ns_),
      snapshots_(scene_ ? SnapshotRing::Sizes{static_cast<std::size_t>(scene_->Vertices_m().cols()),
                                              scene_->Topology().Triangles().Capacity(), kRecentEvents,
                                              scene_->Topology().Log().Capacity()}
                        : SnapshotRing::Sizes{}) {
  if (!scene_) throw std::invalid_argument("session needs a scene");
  tick_index_ = config_.first_tick;
  paused_.store(config_.start_paused);
  if (!port_) throw std::invalid_argument("session needs a port");
  if (!(config_.tick_period_s > 0.0 && config_.tick_period_s <= 0.1)) {
    throw std::invalid_argument("tick period must be in (0, 0.1] s");
  }
  if (!(config_.frame_rate_hz > 0.0 && config_.frame_rate_hz <= 1000.0)) {
    throw std::invalid_argument("frame rate must be in (0, 1000] Hz");
  }
  if (!(config_.pose_slack_s >= 0.0 && config_.pose_slack_s <= config_.pose_timeout_s)) {
    throw std::invalid_argument("pose slack must be in [0, pose timeout]");
  }
  if (!(config_.pose_extrapolation_s >= 0.0 && config_.pose_extrapolation_s <= config_.pose_timeout_s)) {
    throw std::invalid_argument("pose extrapolation must be in [0, pose timeout]");
  }
  const ModelDeadbandConfig& deadband = config_.model_deadband;
  if (!(deadband.jnd >= 0.0 && deadband.jnd <= 1.0 && deadband.floor_N >= 0.0 && deadband.keepalive_s > 0.0 &&
        deadband.keepalive_s <= config_.pose_timeout_s && deadband.probe_depth_m >= 0.0)) {
    throw std::invalid_argument("model deadband: jnd in [0, 1], floor >= 0, keep-alive in (0, pose timeout]");
  }
  part_names_ = std::make_shared<const std::vector<std::string>>(scene_->Topology().PartNames());
  layer_names_ = std::make_shared<const std::vector<std::string>>(scene_->Status().layer_names);
  ticks_per_frame_ = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(1.0 / (config_.frame_rate_hz * config_.tick_period_s))));
  // What every model promises: with a deadband, the next one within its keep-alive.
  force_message_.next_model_within_s = deadband.jnd > 0.0 ? deadband.keepalive_s : 0.0;
  PublishSnapshot(TickInput{});  // viewers joining before the first tick get the initial mesh
}

PoseVerdict Session::OfferPose(const PoseSample& pose) {
  if (source_) {  // a replay: its recording is the only device, and no pose may clock it
    counters_.poses.from_other_devices.fetch_add(1, std::memory_order_relaxed);
    return PoseVerdict::kOtherDevice;
  }
  const PoseVerdict verdict = ownership_.Accept(pose.device_id, pose.seq, pose.received_ns);
  switch (verdict) {
    case PoseVerdict::kOtherDevice:
      counters_.poses.from_other_devices.fetch_add(1, std::memory_order_relaxed);
      break;
    case PoseVerdict::kStale:
      counters_.poses.stale.fetch_add(1, std::memory_order_relaxed);
      break;
    case PoseVerdict::kAccepted:
      counters_.poses.received.fetch_add(1, std::memory_order_relaxed);
      pose_inbox_.Publish(pose);
      break;
  }
  return verdict;
}

std::int64_t Session::PoseDueNs(std::int64_t arrival_ns) const {
  if (!last_tick_took_pose_.load(std::memory_order_relaxed)) return arrival_ns;
  return std::max(arrival_ns, HalfPeriodAfterLastTickNs());
}

std::int64_t Session::HalfPeriodAfterLastTickNs() const {
  return last_tick_start_ns_.load(std::memory_order_relaxed) + period_ns_ / 2;
}

std::int64_t Session::RunTick(std::int64_t due_ns, std::int64_t now_ns) {
  const std::int64_t paced_ns = std::max(due_ns, HalfPeriodAfterLastTickNs());
  last_tick_start_ns_.store(now_ns, std::memory_order_relaxed);
  const TickInput in = source_ ? AssembleReplayInput() : AssembleInput(now_ns);
  last_tick_took_pose_.store(in.fresh_pose, std::memory_order_relaxed);
  if (tick_observer_) tick_observer_(in);
  StepScene(*scene_, in, step_s_);
  // The step's outputs, read once for the counters, the listener and the device.
  const core::LocalForceModel model = scene_->ForceModel();
  const double tool_force_N = scene_->ToolForce_W_N().norm();
  if (listener_) listener_->OnTick(TickOutcome{in, *scene_, model.state, tool_force_N});
  const std::int64_t work_ns = std::max<std::int64_t>(0, common::SteadyNowNs() - now_ns);
  counters_.tick.tick_work_ns.fetch_add(static_cast<std::uint64_t>(work_ns), std::memory_order_relaxed);
  counters_.tick.tick_work.Observe_ns(work_ns);
  RecordTiming(in, due_ns, now_ns, tool_force_N);
  interval_peak_N_ = std::max(interval_peak_N_, tool_force_N);
  if (in.tool.valid && !source_) PublishForceModel(in, model, now_ns);
  if ((in.tick + 1) % ticks_per_frame_ == 0) PublishSnapshot(in);
  return NextDueNs(in, due_ns, paced_ns, now_ns);
}

TickInput Session::AssembleInput(std::int64_t now_ns) {
  TickInput in;
  in.tick = tick_index_++;
  PoseSample pose;
  if (pose_inbox_.TakeIfNew(&pose)) {
    // Several poses since the last tick (a clump after jitter, or losses): the newest wins, the rest are counted.
    if (have_pose_ && pose.device_id == last_pose_.device_id && pose.seq > last_pose_.seq + 1)
      counters_.tick.poses_unused.fetch_add(pose.seq - last_pose_.seq - 1, std::memory_order_relaxed);
    last_pose_ = pose;
    have_pose_ = true;
    pose_taken_ns_ = now_ns;
    in.fresh_pose = true;
  }
  in.tool = last_pose_.tool;
  in.device_id = last_pose_.device_id;
  in.pose_seq = last_pose_.seq;
  const std::int64_t pose_age_ns = now_ns - last_pose_.received_ns;
  if (!have_pose_ || pose_age_ns > pose_timeout_ns_) in.tool.valid = false;  // device gone
  // No new pose (sent sparsely, or late): where the tool has moved on to.
  if (!in.fresh_pose && in.tool.valid && pose_age_ns > 0) {
    const double ahead_s = static_cast<double>(std::min(pose_age_ns, pose_extrapolation_ns_)) * 1e-9;
    in.tool.tip_W_m += ahead_s * in.tool.velocity_W_m_per_s;
  }
  in.paused = paused_.load(std::memory_order_relaxed);
  const std::uint32_t resets = reset_requests_.load(std::memory_order_relaxed);
  in.reset = resets != resets_seen_;
  resets_seen_ = resets;
  return in;
}

// A replay's input: the recording's next one, unless the session is paused
// (and no single step was asked for) or the recording has ended; a reset
// rewinds it with the scene. The recorded pause and reset apply as recorded.
TickInput Session::AssembleReplayInput() {
  TickInput in = last_replayed_;
  in.tick = tick_index_++;
  in.reset = false;
  const std::uint32_t resets = reset_requests_.load(std::memory_order_relaxed);
  const bool rewind = resets != resets_seen_;
  resets_seen_ = resets;
  if (rewind) source_->Rewind();
  bool hold = paused_.load(std::memory_order_relaxed) && !source_->TakeStep();
  if (!hold) {
    TickInput recorded;
    hold = !source_->Next(&recorded);
    if (!hold) {
      in = recorded;
      in.tick = tick_index_ - 1;
      last_replayed_ = recorded;
    }
  }
  in.paused = in.paused || hold;
  in.reset = in.reset || rewind;
  return in;
}

// A streaming device clocks the session: the next tick comes with its next
// pose, and this deadline (one period plus the slack after a device tick —
// after when it would have run had it waited for PoseDueNs's half period)
// only fires if that pose is late. Without a device the session ticks on a
// 1 kHz grid shared by all sessions, so their ticks coalesce into one
// wake-up. After a long stall the schedule re-anchors instead of bursting.
std::int64_t Session::NextDueNs(const TickInput& in, std::int64_t due_ns, std::int64_t paced_ns,
                                std::int64_t now_ns) const {
  std::int64_t next;
  if (in.tool.valid && !source_) {  // a device streams
    next = in.fresh_pose ? paced_ns + period_ns_ + pose_slack_ns_ : due_ns + period_ns_;
  } else {
    next = (due_ns / period_ns_ + 1) * period_ns_;
  }
  if (now_ns - next > 10 * period_ns_) next = (now_ns / period_ns_ + 1) * period_ns_;
  return next;
}

void Session::RecordTiming(const TickInput& in, std::int64_t due_ns, std::int64_t now_ns, double tool_force_N) {
  const std::int64_t lateness_ns = now_ns - due_ns;
  counters_.tick.tick_lateness.Observe_ns(lateness_ns);
  if (lateness_ns > period_ns_) counters_.tick.late_ticks.fetch_add(1, std::memory_order_relaxed);
  AtomicMax(counters_.tick.max_lateness_ns, lateness_ns);
  if (in.fresh_pose) counters_.tick.device_clocked_ticks.fetch_add(1, std::memory_order_relaxed);
  counters_.tick.ticks.fetch_add(1, std::memory_order_relaxed);
  counters_.tick.device_streaming.store(in.tool.valid, std::memory_order_relaxed);
  counters_.tick.owning_device_id.store(in.device_id, std::memory_order_relaxed);
  counters_.tick.sim_time_s.store(scene_->SimTime_s(), std::memory_order_relaxed);
  counters_.tick.numerical_resets.store(scene_->Status().numerical_resets, std::memory_order_relaxed);
  if (in.reset) counters_.tick.peak_tool_force_N.store(0.0);
  AtomicMax(counters_.tick.peak_tool_force_N, tool_force_N);
}

void Session::PublishForceModel(const TickInput& in, const core::LocalForceModel& model, std::int64_t now_ns) {
  ForceModelMessage& m = force_message_;
  // Paused: the tissue is frozen, so the device gets no force (safe default).
  m.model = in.paused ? core::LocalForceModel{} : model;
  if (in.device_id != m.device_id) model_deadband_.Forget();  // a new device holds no model yet
  if (!model_deadband_.Offer(m.model, in.tool, now_ns)) {
    counters_.tick.force_models_held.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  m.device_id = in.device_id;
  m.seq = force_seq_++;
  m.echo_pose_seq = in.pose_seq;
  m.echo_pose_held_ns = now_ns - pose_taken_ns_;  // 0 on the tick that took it
  m.tool_force_W_N = in.paused ? Eigen::Vector3d::Zero() : scene_->ToolForce_W_N();
  m.t_server_ns = common::SteadyNowNs();
  // A refused write is counted by the port (ServerDds counters).
  if (port_->WriteForceModel(m)) {
    counters_.tick.force_models_sent.fetch_add(1, std::memory_order_relaxed);
    if (in.fresh_pose) counters_.tick.pose_to_model.Observe_ns(m.t_server_ns - last_pose_.received_ns);
  }
}

void Session::WantMeshUntil(std::int64_t until_ns) {
  std::int64_t was = mesh_wanted_until_ns_.load(std::memory_order_relaxed);
  while (was < until_ns && !mesh_wanted_until_ns_.compare_exchange_weak(was, until_ns, std::memory_order_relaxed)) {
  }
}

void Session::PublishSnapshot(const TickInput& in) {
  std::shared_ptr<SceneSnapshot> s = snapshots_.Acquire();
  if (!s) {
    counters_.tick.snapshots_skipped.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  s->id = ++snapshot_id_;
  interval_peaks_N_[s->id % SceneSnapshot::kPeakIntervals] = interval_peak_N_;
  interval_peak_N_ = 0.0;
  s->interval_peak_N = interval_peaks_N_;
  s->sim_time_s = scene_->SimTime_s();
  s->paused = in.paused;
  // The first snapshot (published at creation) always has the mesh.
  s->has_mesh = s->id == 1 || counters_.viewers.connected.load(std::memory_order_relaxed) > 0 ||
                common::SteadyNowNs() < mesh_wanted_until_ns_.load(std::memory_order_relaxed);
  if (s->has_mesh) {
    CopyMesh(scene_->Vertices_m(), scene_->Topology(), topology_taken_.load(std::memory_order_acquire), s.get());
  }
  s->part_names = part_names_;
  s->layer_names = layer_names_;
  s->tool = last_pose_.tool;
  s->tool.valid = in.tool.valid;
  s->tool_force_W_N = scene_->ToolForce_W_N();
  s->contact = scene_->ForceModel().state;
  s->current_layer = scene_->Status().current_layer;
  s->tip_depth_m = scene_->Status().tip_depth_m;
  const auto events = scene_->Events();
  const std::size_t first = events.size() > kRecentEvents ? events.size() - kRecentEvents : 0;
  s->recent_events.assign(events.begin() + static_cast<std::ptrdiff_t>(first), events.end());
  s->events_total = scene_->EventsTotal();
  snapshot_outbox_.Publish(std::move(s));
  if (listener_) listener_->OnSnapshotPublished();
}

}  // namespace hapsim::service
