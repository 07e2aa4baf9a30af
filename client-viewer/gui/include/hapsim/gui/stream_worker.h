// Keeps a LiveScene fed from one session's frame stream on a thread of its
// own, through everything a long-running window meets: the server not up
// yet, a server restart (reconnects every second), the session closed under
// it (says so, and picks the session up again if it is re-created), a
// malformed frame or a gap (ViewerClient resubscribes for a keyframe).
#pragma once
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "hapsim/gui/live_scene.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/viewer_client.h"

namespace hapsim::gui {

class StreamWorker {
 public:
  // `recorder` (may be null) gets every applied frame, as it came.
  StreamWorker(viewer::Connection connection, viewer::ViewerOptions options, LiveScene* scene,
               viewer::FrameLogWriter* recorder = nullptr);
  ~StreamWorker();  // stops and joins
  void Stop();
  std::uint64_t reconnects() const { return reconnects_; }
  // Stops, joins and returns the mesh as the last stream left it (the
  // stream's quantised positions, as the headless viewer writes them, for
  // --obj/--export), or nothing if no keyframe ever came.
  std::optional<viewer::CompactMesh> StopAndTakeMesh();

 private:
  void Loop();

  viewer::Connection connection_;
  viewer::ViewerOptions options_;
  LiveScene* scene_;
  viewer::FrameLogWriter* recorder_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> reconnects_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  viewer::ViewerClient* client_ = nullptr;  // the running one, guarded by mutex_
  std::optional<viewer::CompactMesh> last_mesh_;  // of the last stream that ended, guarded by mutex_
  std::thread thread_;
};

}  // namespace hapsim::gui
