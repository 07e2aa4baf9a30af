#include "hapsim/service/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <spdlog/spdlog.h>

#include "hapsim/runtime/clock.h"
#include "hapsim/service/viewer_link.h"

namespace hapsim::service {

namespace {

void AtomicMax(std::atomic<double>& a, double v) {
  double cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

}  // namespace

Session::Session(SessionConfig config, std::function<void()> wake_dds)
    : config_(std::move(config)), wake_dds_(std::move(wake_dds)) {
  if (!(config_.tick_period_s > 0.0 && config_.tick_period_s <= 0.1)) {
    throw std::invalid_argument("tick period must be in (0, 0.1] s");
  }
  if (!(config_.frame_rate_hz > 0.0 && config_.frame_rate_hz <= 1000.0)) {
    throw std::invalid_argument("frame rate must be in (0, 1000] Hz");
  }
  scene_ = core::MakeScene({config_.scene, config_.params});
  ticks_per_frame_ = std::max<std::uint64_t>(
      1, static_cast<std::uint64_t>(std::llround(1.0 / (config_.frame_rate_hz * config_.tick_period_s))));
  PublishSnapshot();  // viewers joining before the first tick get the initial mesh
}

Session::~Session() { Stop(); }

void Session::Start() {
  if (thread_.joinable()) return;
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
}

void Session::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

// Fixed-rate loop on absolute deadlines. Sim time advances by exactly one
// period per tick whatever the wall clock does, so results stay
// deterministic; lateness is counted, and after a long stall the schedule is
// re-anchored instead of running a burst of catch-up ticks.
void Session::Run() {
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(
      std::chrono::duration<double>(config_.tick_period_s));
  auto next = clock::now();
  std::uint64_t tick = 0;
  while (!stop_.load(std::memory_order_relaxed)) {
    std::this_thread::sleep_until(next);
    const auto now = clock::now();
    if (now - next > period) {
      counters_.deadline_misses.fetch_add(1, std::memory_order_relaxed);
      if (now - next > 10 * period) next = now;  // stalled: re-anchor
    }
    Tick(tick++, runtime::SteadyNowNs());
    next += period;
  }
}

void Session::Tick(std::uint64_t tick_index, std::int64_t now_ns) {
  // 1. The one input point: newest pose, if any.
  PoseSample pose;
  if (pose_inbox_.TakeIfNew(&pose)) {
    last_pose_ = pose;
    have_pose_ = true;
  }
  core::ToolInput tool = last_pose_.tool;
  const double pose_age_s = have_pose_ ? static_cast<double>(now_ns - last_pose_.received_ns) * 1e-9 : 1e9;
  if (!have_pose_ || pose_age_s > config_.pose_timeout_s) tool.valid = false;  // device gone

  // 2. Control requests.
  const std::uint32_t resets = reset_requests_.load(std::memory_order_relaxed);
  if (resets != resets_seen_) {
    resets_seen_ = resets;
    scene_->Reset();
    counters_.peak_tool_force_N.store(0.0);
  }

  // 3. Step (skipped while paused).
  if (!paused_.load(std::memory_order_relaxed)) {
    scene_->Step(tool, config_.tick_period_s);
  }
  counters_.ticks.fetch_add(1, std::memory_order_relaxed);
  counters_.sim_time_s.store(scene_->SimTime_s(), std::memory_order_relaxed);
  counters_.numerical_resets.store(scene_->Status().numerical_resets, std::memory_order_relaxed);
  AtomicMax(counters_.peak_tool_force_N, scene_->ToolForce_W_N().norm());

  // 4. Publish: force model every tick while a device is streaming, snapshot
  //    at the frame rate.
  if (tool.valid) PublishForceModel();
  if ((tick_index + 1) % ticks_per_frame_ == 0) PublishSnapshot();
}

void Session::PublishForceModel() {
  hapsim_dds_LocalForceModel m{};
  m.device_id = last_pose_.device_id;
  std::strncpy(m.session, config_.id.c_str(), sizeof m.session - 1);
  m.seq = force_seq_++;
  m.echo_pose_seq = last_pose_.seq;
  m.t_server_ns = runtime::SteadyNowNs();
  // Paused: the tissue is frozen, so the device gets no force (safe default).
  const core::LocalForceModel model = paused_.load() ? core::LocalForceModel{} : scene_->ForceModel();
  m.state = static_cast<std::uint8_t>(model.state);
  const Eigen::Vector3d f = paused_.load() ? Eigen::Vector3d::Zero() : scene_->ToolForce_W_N();
  for (int i = 0; i < 3; ++i) {
    m.anchor_m[i] = model.anchor_W_m[i];
    m.normal[i] = model.normal_W[i];
    m.feedforward_n[i] = model.feedforward_W_N[i];
    m.tool_force_n[i] = f[i];
  }
  m.stiffness_n_per_m = model.stiffness_N_per_m;
  m.damping_ns_per_m = model.damping_Ns_per_m;
  force_outbox_.Publish(m);
  wake_dds_();
}

void Session::PublishSnapshot() {
  auto s = std::make_shared<SceneSnapshot>();
  s->id = ++snapshot_id_;
  s->sim_time_s = scene_->SimTime_s();
  s->paused = paused_.load();
  s->vertices_m = scene_->Vertices_m();
  s->topology_version = scene_->TopologyVersion();
  if (s->topology_version != shared_topology_version_ || !triangles_) {
    // Topology changed: share fresh copies with every stream from now on.
    triangles_ = std::make_shared<const std::vector<std::uint32_t>>(scene_->Triangles());
    parts_ = std::make_shared<const std::vector<core::SurfacePart>>(scene_->Parts());
    layer_names_ = std::make_shared<const std::vector<std::string>>(scene_->Status().layer_names);
    shared_topology_version_ = s->topology_version;
  }
  s->triangles = triangles_;
  s->parts = parts_;
  s->layer_names = layer_names_;
  s->tool = last_pose_.tool;
  s->tool.valid = have_pose_;
  s->tool_force_W_N = scene_->ToolForce_W_N();
  s->contact = scene_->ForceModel().state;
  s->current_layer = scene_->Status().current_layer;
  s->tip_depth_m = scene_->Status().tip_depth_m;
  const auto events = scene_->Events();
  constexpr std::size_t kRecent = 64;
  const std::size_t first = events.size() > kRecent ? events.size() - kRecent : 0;
  s->recent_events.assign(events.begin() + static_cast<std::ptrdiff_t>(first), events.end());
  s->events_total = scene_->EventsTotal();
  snapshot_outbox_.Publish(std::move(s));
}

void Session::AddViewer(std::shared_ptr<ViewerLink> link) {
  std::lock_guard lock(viewers_mutex_);
  viewers_.push_back(std::move(link));
  counters_.viewers.store(static_cast<std::uint32_t>(viewers_.size()));
}

void Session::RemoveViewer(const ViewerLink* link) {
  std::lock_guard lock(viewers_mutex_);
  std::erase_if(viewers_, [link](const auto& v) { return v.get() == link; });
  counters_.viewers.store(static_cast<std::uint32_t>(viewers_.size()));
}

std::vector<std::shared_ptr<ViewerLink>> Session::Viewers() const {
  std::lock_guard lock(viewers_mutex_);
  return viewers_;
}

void Session::SetLatestSnapshot(std::shared_ptr<const SceneSnapshot> s) {
  std::lock_guard lock(snapshot_mutex_);
  latest_snapshot_ = std::move(s);
}

std::shared_ptr<const SceneSnapshot> Session::LatestSnapshot() const {
  std::lock_guard lock(snapshot_mutex_);
  return latest_snapshot_;
}

}  // namespace hapsim::service
