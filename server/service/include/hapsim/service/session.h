// A session: one scene stepped at a fixed rate (1 kHz for haptic scenes) on
// its own thread. It talks to the rest of the server only through
// latest-value mailboxes, so the tick never waits for DDS or gRPC:
//   pose in      (DDS thread  -> tick)
//   force model  (tick -> DDS thread, which then writes it)
//   snapshot     (tick -> frame pump, at the viewer frame rate)
// Control requests (pause, resume, reset) are atomics read once per tick.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/runtime/latest_value.h"
#include "hapsim/service/scene_snapshot.h"
#include "haptics.h"

namespace hapsim::service {

class ViewerLink;

struct SessionConfig {
  std::string id;
  std::string scene = "tissue_block";
  std::string owner;
  std::map<std::string, double> params;
  double tick_period_s = 0.001;      // physics tick (1 kHz)
  double frame_rate_hz = 60.0;       // snapshots for viewers
  double pose_timeout_s = 0.25;      // no pose for this long: the tool is absent
};

// A pose accepted by the DDS thread.
struct PoseSample {
  core::ToolInput tool;
  std::uint32_t device_id = 0;
  std::uint64_t seq = 0;
  std::int64_t received_ns = 0;  // server steady clock
};

// Counters readable from any thread (gRPC handlers, logs).
struct SessionCounters {
  std::atomic<std::uint64_t> ticks{0};
  std::atomic<std::uint64_t> deadline_misses{0};
  std::atomic<std::uint64_t> poses_received{0};
  std::atomic<std::uint64_t> poses_rejected{0};
  std::atomic<std::uint64_t> force_models_sent{0};
  std::atomic<std::uint64_t> numerical_resets{0};
  std::atomic<double> sim_time_s{0.0};
  std::atomic<double> peak_tool_force_N{0.0};
  std::atomic<std::uint32_t> viewers{0};
};

class Session {
 public:
  // Builds the scene (throws std::invalid_argument on bad scene/params).
  // wake_dds is called (cheap, thread-safe) after each force model is posted.
  Session(SessionConfig config, std::function<void()> wake_dds);
  ~Session();  // stops the tick thread
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  void Start();
  void Stop();

  const SessionConfig& config() const { return config_; }
  const std::string& id() const { return config_.id; }
  SessionCounters& counters() { return counters_; }
  const SessionCounters& counters() const { return counters_; }
  bool paused() const { return paused_.load(); }

  // DDS thread only.
  void OfferPose(const PoseSample& pose) { pose_inbox_.Publish(pose); }
  bool TakeForceModel(hapsim_dds_LocalForceModel* out) { return force_outbox_.TakeIfNew(out); }

  // Frame pump only.
  bool TakeSnapshot(std::shared_ptr<const SceneSnapshot>* out) { return snapshot_outbox_.TakeIfNew(out); }

  // Any thread.
  void RequestPause(bool pause) { paused_.store(pause); }
  void RequestReset() { reset_requests_.fetch_add(1); }

  // Viewer streams of this session (frame pump and gRPC threads).
  void AddViewer(std::shared_ptr<ViewerLink> link);
  void RemoveViewer(const ViewerLink* link);
  std::vector<std::shared_ptr<ViewerLink>> Viewers() const;

  // The newest snapshot the frame pump has seen (for GetSnapshot).
  void SetLatestSnapshot(std::shared_ptr<const SceneSnapshot> s);
  std::shared_ptr<const SceneSnapshot> LatestSnapshot() const;

 private:
  void Run();
  void Tick(std::uint64_t tick_index, std::int64_t now_ns);
  void PublishForceModel();
  void PublishSnapshot();

  SessionConfig config_;
  std::function<void()> wake_dds_;
  std::unique_ptr<core::Scene> scene_;
  SessionCounters counters_;

  runtime::LatestValue<PoseSample> pose_inbox_;
  runtime::LatestValue<hapsim_dds_LocalForceModel> force_outbox_;
  runtime::LatestValue<std::shared_ptr<const SceneSnapshot>> snapshot_outbox_;

  std::atomic<bool> paused_{false};
  std::atomic<std::uint32_t> reset_requests_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;

  // Tick-thread state.
  PoseSample last_pose_;
  bool have_pose_ = false;
  std::uint64_t force_seq_ = 0;
  std::uint64_t snapshot_id_ = 0;
  std::uint32_t resets_seen_ = 0;
  std::uint64_t ticks_per_frame_ = 16;
  std::shared_ptr<const std::vector<std::uint32_t>> triangles_;
  std::shared_ptr<const std::vector<core::SurfacePart>> parts_;
  std::shared_ptr<const std::vector<std::string>> layer_names_;
  std::uint64_t shared_topology_version_ = ~0ull;

  mutable std::mutex viewers_mutex_;
  std::vector<std::shared_ptr<ViewerLink>> viewers_;
  mutable std::mutex snapshot_mutex_;
  std::shared_ptr<const SceneSnapshot> latest_snapshot_;
};

}  // namespace hapsim::service
