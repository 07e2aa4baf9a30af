#include "hapsim/gui/stream_worker.h"

#include <chrono>

#include <spdlog/spdlog.h>

namespace hapsim::gui {

StreamWorker::StreamWorker(viewer::Connection connection, viewer::ViewerOptions options, LiveScene* scene,
                           viewer::FrameLogWriter* recorder)
    : connection_(std::move(connection)), options_(std::move(options)), scene_(scene), recorder_(recorder) {
  options_.max_frames = 0;  // the window decides when to stop
  options_.max_seconds = 0.0;
  options_.token = connection_.token;
  options_.recorder = recorder_;
  options_.on_frame = [this, live = false](const viewer::ViewerFrame& frame, const viewer::MeshCache& mesh) mutable {
    if (!live || frame.keyframe) {
      scene_->SetConnection("live");
      live = true;
    }
    scene_->OnFrame(frame, mesh);
  };
  thread_ = std::thread([this] { Loop(); });
}

StreamWorker::~StreamWorker() {
  Stop();
  if (thread_.joinable()) thread_.join();
}

void StreamWorker::Stop() {
  stop_ = true;
  std::lock_guard lock(mutex_);
  if (client_) client_->Stop();
  wake_.notify_all();
}

std::optional<viewer::CompactMesh> StreamWorker::StopAndTakeMesh() {
  Stop();
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  return std::move(last_mesh_);
}

void StreamWorker::Loop() {
  std::shared_ptr<grpc::Channel> channel;
  try {
    channel = viewer::MakeViewerChannel(connection_);
  } catch (const std::exception& e) {
    scene_->SetConnection(std::string("cannot connect: ") + e.what());
    return;
  }
  viewer::ViewerOptions options = options_;
  options.connect_timeout_s = std::min(options.connect_timeout_s, 2.0);  // retried below
  bool first = true;
  while (!stop_) {
    if (!first) ++reconnects_;
    scene_->SetConnection(first ? "connecting to " + connection_.address : "reconnecting to " + connection_.address);
    first = false;
    viewer::ViewerClient client(channel, options);
    {
      std::lock_guard lock(mutex_);
      if (stop_) break;
      client_ = &client;
    }
    client.Run();
    {
      std::lock_guard lock(mutex_);
      client_ = nullptr;
      if (client.mesh().has_mesh()) last_mesh_ = client.mesh().Compact();
    }
    if (stop_) break;
    const std::string why = client.stats().final_status;
    spdlog::warn("viewer stream of session '{}' lost: {}; retrying in 1 s", options.session, why);
    scene_->SetConnection("lost: " + why + " — retrying");
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_.load(); });
  }
}

}  // namespace hapsim::gui
