#include "hapsim/gui/live_scene.h"

#include <limits>

#include "hapsim/viewer/frame_decoder.h"

namespace hapsim::gui {

std::string SceneView::LayerName(int layer) const {
  if (layer < 0 || static_cast<std::size_t>(layer) >= layer_names.size()) return "";
  return layer_names[static_cast<std::size_t>(layer)];
}

namespace {

void CopyLiveTriangles(const viewer::MeshCache& cache, SceneView* s) {
  auto list = std::make_shared<TriangleList>();
  list->vertices.reserve(3 * cache.live_triangle_count());
  list->parts.reserve(cache.live_triangle_count());
  for (std::size_t t = 0; t < cache.triangle_slots(); ++t) {
    if (!cache.triangle_live(t)) continue;
    const auto& tri = cache.triangle(t);
    list->vertices.insert(list->vertices.end(), tri.begin(), tri.end());
    list->parts.push_back(cache.triangle_part(t));
  }
  list->part_names = cache.part_names();
  s->triangles = std::move(list);
  s->layer_names = cache.layer_names();
  ++s->topology_stamp;
}

bool SameTool(const viewer::FrameTool& a, const viewer::FrameTool& b) {
  return a.valid == b.valid && a.tip_m == b.tip_m && a.orientation.coeffs() == b.orientation.coeffs() &&
         a.force_N == b.force_N && a.contact_state == b.contact_state;
}

}  // namespace

bool LiveScene::ChangesNothing(const viewer::ViewerFrame& frame) const {
  const SceneView& s = state_;
  return s.triangles && !frame.keyframe && !frame.topology_edits && frame.events.empty() && frame.moved_vertices == 0 &&
         frame.sim_time_s == s.sim_time_s && frame.paused == s.paused && frame.current_layer == s.current_layer &&
         frame.tip_depth_m == s.tip_depth_m && SameTool(frame.tool, last_tool_);
}

std::uint64_t LiveScene::FramesReceived() const {
  std::lock_guard lock(mutex_);
  return state_.frames;
}

std::uint64_t LiveScene::LastSeq() const {
  std::lock_guard lock(mutex_);
  return state_.seq;
}

// The cache's quantised positions straight into a buffer the render thread
// will share (the one copy of the positions on their way to the GPU), with
// the live vertices' box in the same pass.
void LiveScene::TakePositions(const viewer::MeshCache& mesh) {
  const std::vector<std::int32_t>& q = mesh.positions_q();
  const double quantum_m = mesh.quantum_m();
  const std::shared_ptr<std::vector<float>> buffer = position_buffers_.Writable();
  buffer->resize(q.size());
  float* out = buffer->data();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (std::size_t v = 0; 3 * v < q.size(); ++v) {
    const Eigen::Vector3d p(q[3 * v] * quantum_m, q[3 * v + 1] * quantum_m, q[3 * v + 2] * quantum_m);
    for (int k = 0; k < 3; ++k) out[3 * v + static_cast<std::size_t>(k)] = static_cast<float>(p[k]);
    if (!mesh.vertex_live(v)) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  state_.positions_m = SharedPositions(buffer);
  if (lo.x() <= hi.x()) {
    state_.lo_m = lo;
    state_.hi_m = hi;
  }
}

void LiveScene::TakeEventsAndHistory(const viewer::ViewerFrame& frame) {
  SceneView& s = state_;
  for (const viewer::FrameEvent& e : frame.events) {
    if (e.kind == viewer::EventKind::kReset) s.history.clear();
    s.events.push_back(e);
    if (s.events.size() > kMaxEvents) s.events.pop_front();
  }
  // A keyframe after a reset or re-subscription may go back in time.
  if (!s.history.empty() && frame.sim_time_s < s.history.back().t_s) s.history.clear();
  if (s.history.size() >= kMaxHistory) s.history.DropOldest(kMaxHistory / 4);
  s.history.push_back({frame.sim_time_s, frame.peak_force_N, frame.tip_depth_m});
}

void LiveScene::OnFrame(const viewer::ViewerFrame& frame, const viewer::MeshCache& mesh) {
  std::lock_guard lock(mutex_);
  SceneView& s = state_;
  // A paused session keeps streaming frames that change nothing drawn:
  // counted, but the version stays, so the window does not redraw for them.
  if (ChangesNothing(frame)) {
    s.seq = frame.seq;
    ++s.frames;
    return;
  }
  last_tool_ = frame.tool;
  if (frame.keyframe || frame.topology_edits || !s.triangles) CopyLiveTriangles(mesh, &s);
  TakePositions(mesh);
  s.seq = frame.seq;
  s.sim_time_s = frame.sim_time_s;
  s.current_layer = frame.current_layer;
  s.tip_depth_m = frame.tip_depth_m;
  s.paused = frame.paused;
  s.tool = frame.tool;
  TakeEventsAndHistory(frame);
  ++s.frames;
  ++s.version;
}

void LiveScene::OnFrame(const hapsim::v1::Frame& wire, const viewer::MeshCache& mesh) {
  viewer::ViewerFrame frame;
  viewer::DecodeFrame(wire, mesh, &frame);
  OnFrame(frame, mesh);
}

void LiveScene::SetConnection(const std::string& state) {
  std::lock_guard lock(mutex_);
  if (state_.connection == state) return;
  state_.connection = state;
  ++connection_stamp_;
}

bool LiveScene::CopyIfNewer(SceneView* out) const {
  std::lock_guard lock(mutex_);
  if (out->version == state_.version && copied_connection_stamp_ == connection_stamp_) return false;
  *out = state_;  // positions and triangles are shared, the history's full chunks too
  copied_connection_stamp_ = connection_stamp_;
  return true;
}

void LiveScene::Clear() {
  std::lock_guard lock(mutex_);
  const std::string connection = state_.connection;
  const std::uint64_t version = state_.version, stamp = state_.topology_stamp;
  state_ = SceneView();
  state_.connection = connection;
  state_.version = version + 1;
  state_.topology_stamp = stamp + 1;
}

}  // namespace hapsim::gui
