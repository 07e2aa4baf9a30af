// Subscribes to a session's frame stream, decodes each frame once
// (FrameDecoder) and keeps a MeshCache current. On a seq gap or topology
// mismatch it cancels the stream and subscribes again, which starts the new
// stream with a keyframe.
#pragma once
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "hapsim/v1/viewer.grpc.pb.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/frame_decoder.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/viewer_frame.h"

namespace hapsim::viewer {

struct ViewerOptions {
  std::string session = "demo";
  std::string name = "hapsim-viewer";
  double max_rate_hz = 0.0;          // 0: the server's frame rate
  std::uint32_t ack_window = 2;      // unacknowledged frames allowed (0: no app-level flow control)
  std::uint64_t max_frames = 0;      // stop after this many frames (0: no limit)
  double max_seconds = 0.0;          // stop after this long (0: no limit)
  double connect_timeout_s = 10.0;
  std::string token;                 // bearer token (servers with a class config)
  // Fault injection for tests: pretend the frame with this seq of the first
  // stream was lost (not applied), forcing gap detection and a resubscribe.
  std::int64_t debug_drop_seq = -1;
  // Gets every frame whose mesh applied, as it came (--record); not owned.
  FrameLogWriter* recorder = nullptr;
  // Called on the client's thread for every frame read, decoded, before its
  // mesh is applied — a frame the cache then refuses too, since its events
  // happened (tallies of what happened to the tissue).
  std::function<void(const ViewerFrame&)> on_received;
  // Called on the client's thread after a frame's mesh is applied (an
  // on-screen viewer copies what it draws).
  std::function<void(const ViewerFrame&, const MeshCache&)> on_frame;
};

// The stream as a transport: what arrived and how it went. What happened
// in the scene is the caller's to tally (EventTally, through on_received).
struct ViewerStats {
  std::uint64_t frames = 0, keyframes = 0, deltas = 0, bytes = 0;
  std::uint64_t gaps = 0, topology_mismatches = 0, malformed = 0, resubscribes = 0;
  double first_sim_time_s = 0.0;  // of the first frame received: with the last, the frame rate once streaming
  double last_sim_time_s = 0.0;
  double peak_tool_force_N = 0.0;  // the highest ViewerFrame::peak_force_N read
  std::string final_status;        // how the last stream ended
};

// Channel with the small HTTP/2 windows that keep a slow viewer's lag short
// (see docs/architecture.md, "gRPC backpressure").
std::shared_ptr<grpc::Channel> MakeViewerChannel(const std::string& address);
std::shared_ptr<grpc::Channel> MakeViewerChannel(const Connection& connection);  // + TLS (throws like MakeChannel)

class ViewerClient {
 public:
  ViewerClient(std::shared_ptr<grpc::Channel> channel, ViewerOptions options);
  // Runs until a limit, Stop(), or a non-recoverable error. Returns true if
  // it ended by a limit or Stop(); false with stats().final_status set otherwise.
  bool Run();
  void Stop();  // thread-safe (signal handler thread)

  const MeshCache& mesh() const { return decoder_.mesh(); }
  const ViewerStats& stats() const { return stats_; }

 private:
  using Clock = std::chrono::steady_clock;
  enum class StreamEnd { kByServer, kLimit, kResubscribe };
  struct StreamResult {
    StreamEnd end;
    grpc::Status status;
  };

  bool WaitForServer();
  // One Subscribe stream, from its keyframe until it ends, a limit is
  // reached or a frame is refused.
  StreamResult RunStream(grpc::ClientContext* context, Clock::time_point deadline, bool first_stream);
  void SetActiveContext(grpc::ClientContext* context);
  // Decodes, counts and applies one frame; false if the cache refused it.
  bool TakeFrame(const hapsim::v1::Frame& wire, bool first_stream);
  void CountFrame(const hapsim::v1::Frame& wire, const ViewerFrame& frame);
  void CountRefusal(ApplyResult result);

  std::unique_ptr<hapsim::v1::ViewerService::Stub> stub_;
  std::shared_ptr<grpc::Channel> channel_;
  ViewerOptions options_;
  FrameDecoder decoder_;
  ViewerStats stats_;
  std::mutex context_mutex_;
  grpc::ClientContext* active_context_ = nullptr;
  std::atomic<bool> stop_{false};
};

}  // namespace hapsim::viewer
