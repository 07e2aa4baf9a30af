// Subscribes to a session's frame stream and keeps a MeshCache current. On a
// seq gap or topology mismatch it cancels the stream and subscribes again,
// which starts the new stream with a keyframe.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "hapsim/v1/viewer.grpc.pb.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/mesh_cache.h"

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
  // Called on the client's thread after each frame is applied to the cache
  // (an on-screen viewer copies what it draws; a recorder writes the frame).
  std::function<void(const hapsim::v1::Frame&, const MeshCache&)> on_frame;
};

struct ViewerStats {
  std::uint64_t frames = 0, keyframes = 0, deltas = 0, bytes = 0;
  std::uint64_t gaps = 0, topology_mismatches = 0, malformed = 0, resubscribes = 0;
  double last_sim_time_s = 0.0;
  double peak_tool_force_N = 0.0;
  std::string last_contact_state;
  std::map<std::string, std::uint64_t> events;  // kind -> count
  // Punctures in order, as "layer@depth_mm" (layer name from the keyframe).
  std::vector<std::string> punctures;
  std::uint64_t topology_frames = 0;            // frames that carried topology edits (a cut)
  std::vector<double> incisions_mm;             // each cut_end event's incision length
  std::string final_status;                     // how the last stream ended
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

  const MeshCache& mesh() const { return cache_; }
  const ViewerStats& stats() const { return stats_; }

 private:
  std::unique_ptr<hapsim::v1::ViewerService::Stub> stub_;
  std::shared_ptr<grpc::Channel> channel_;
  ViewerOptions options_;
  MeshCache cache_;
  ViewerStats stats_;
  std::mutex context_mutex_;
  grpc::ClientContext* active_context_ = nullptr;
  std::atomic<bool> stop_{false};
};

}  // namespace hapsim::viewer
