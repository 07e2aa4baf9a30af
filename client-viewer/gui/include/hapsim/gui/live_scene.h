// What the on-screen viewer draws, fed from the frame stream. The gRPC
// client's thread calls OnFrame after each applied frame; the render thread
// copies the newest state with CopyIfNewer. The mesh stays in the cache's
// slots (positions of every slot, triangles naming slots), so a delta only
// rewrites positions and a cut only rebuilds the triangle list. The copy
// shares what is large (positions, triangles, the force history's full
// chunks) instead of copying it.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hapsim/gui/force_history.h"
#include "hapsim/gui/shared_positions.h"
#include "hapsim/v1/viewer.pb.h"
#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/viewer_frame.h"

namespace hapsim::gui {

// The live triangles; shared between copies until the topology changes.
struct TriangleList {
  std::vector<std::uint32_t> vertices;  // 3 vertex slots per live triangle
  std::vector<std::uint16_t> parts;     // 1 per live triangle: index into part_names
  std::vector<std::string> part_names;
};

struct SceneView {
  std::uint64_t version = 0;         // bumps with every frame that changes what is drawn
  std::uint64_t topology_stamp = 0;  // bumps when the triangle list changes
  std::uint64_t seq = 0;
  SharedPositions positions_m;                    // 3 per vertex slot
  std::shared_ptr<const TriangleList> triangles;  // null before the first keyframe
  std::vector<std::string> layer_names;
  Eigen::Vector3d lo_m = Eigen::Vector3d::Zero(), hi_m = Eigen::Vector3d::Zero();  // live vertices' box
  viewer::FrameTool tool;
  int current_layer = -1;
  double tip_depth_m = 0.0, sim_time_s = 0.0;
  bool paused = false;
  std::deque<viewer::FrameEvent> events;  // newest last, at most kMaxEvents
  ForceHistory history;                   // since the last reset, at most kMaxHistory (oldest dropped)
  std::uint64_t frames = 0;
  std::string connection = "connecting";  // what the stream is doing, for the status line

  std::string LayerName(int layer) const;
};

class LiveScene {
 public:
  static constexpr std::size_t kMaxEvents = 200;
  static constexpr std::size_t kMaxHistory = 30000;

  // `mesh` holds the mesh with the frame applied.
  void OnFrame(const viewer::ViewerFrame& frame, const viewer::MeshCache& mesh);
  // For a caller holding the wire frame it applied to `mesh` (tests,
  // benchmarks): decodes it (viewer::DecodeFrame), then OnFrame.
  void OnFrame(const hapsim::v1::Frame& wire, const viewer::MeshCache& mesh);
  void SetConnection(const std::string& state);
  // Copies the state into *out when it is newer than out->version (or the
  // connection line changed); returns whether it copied.
  bool CopyIfNewer(SceneView* out) const;
  // Forgets the mesh (a new session is watched).
  void Clear();
  // Frames received, including those that changed nothing drawn (which
  // do not bump the version a copy sees).
  std::uint64_t FramesReceived() const;
  std::uint64_t LastSeq() const;  // of the last frame received

 private:
  // mutex_ held by all three.
  bool ChangesNothing(const viewer::ViewerFrame& frame) const;
  void TakePositions(const viewer::MeshCache& mesh);
  void TakeEventsAndHistory(const viewer::ViewerFrame& frame);

  mutable std::mutex mutex_;
  SceneView state_;
  viewer::FrameTool last_tool_;  // of the last frame that changed something
  PositionBuffers position_buffers_;
  std::uint64_t connection_stamp_ = 0;
  mutable std::uint64_t copied_connection_stamp_ = 0;
};

}  // namespace hapsim::gui
