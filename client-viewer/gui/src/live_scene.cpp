#include "hapsim/gui/live_scene.h"

#include <algorithm>
#include <limits>

namespace hapsim::gui {

std::string SceneView::LayerName(int layer) const {
  if (layer < 0 || static_cast<std::size_t>(layer) >= layer_names.size()) return "";
  return layer_names[static_cast<std::size_t>(layer)];
}

namespace {

void CopyTriangles(const viewer::MeshCache& cache, SceneView* s) {
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

void CopyPositions(const viewer::MeshCache& cache, SceneView* s) {
  const Eigen::Matrix3Xd p = cache.Vertices_m();
  s->positions_m.resize(static_cast<std::size_t>(3 * p.cols()));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    for (int k = 0; k < 3; ++k) s->positions_m[static_cast<std::size_t>(3 * v + k)] = static_cast<float>(p(k, v));
    if (!cache.vertex_live(static_cast<std::size_t>(v))) continue;
    lo = lo.cwiseMin(p.col(v));
    hi = hi.cwiseMax(p.col(v));
  }
  if (lo.x() <= hi.x()) {
    s->lo_m = lo;
    s->hi_m = hi;
  }
}

template <class Repeated>
bool SameValues(const Repeated& a, const Repeated& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

bool SameTool(const hapsim::v1::ToolState& a, const hapsim::v1::ToolState& b) {
  return SameValues(a.tip_m(), b.tip_m()) && SameValues(a.orientation_wxyz(), b.orientation_wxyz()) &&
         SameValues(a.force_n(), b.force_n()) && a.contact_state() == b.contact_state();
}

}  // namespace

bool LiveScene::ChangesNothing(const hapsim::v1::Frame& frame) const {
  const SceneView& s = state_;
  return s.triangles && !frame.has_keyframe() && !frame.has_topology() && frame.events_size() == 0 &&
         frame.delta().index_gaps_size() == 0 && frame.sim_time_s() == s.sim_time_s && frame.paused() == s.paused &&
         frame.current_layer() == s.current_layer && frame.tip_depth_m() == s.tip_depth_m &&
         SameTool(frame.tool(), last_tool_);
}

std::uint64_t LiveScene::FramesReceived() const {
  std::lock_guard lock(mutex_);
  return state_.frames;
}

std::uint64_t LiveScene::LastSeq() const {
  std::lock_guard lock(mutex_);
  return state_.seq;
}

void LiveScene::OnFrame(const hapsim::v1::Frame& frame, const viewer::MeshCache& cache) {
  std::lock_guard lock(mutex_);
  SceneView& s = state_;
  // A paused session keeps streaming frames that change nothing drawn:
  // counted, but the version stays, so the window does not redraw for them.
  if (ChangesNothing(frame)) {
    s.seq = frame.seq();
    ++s.frames;
    return;
  }
  last_tool_ = frame.tool();
  if (frame.has_keyframe() || frame.has_topology() || !s.triangles) CopyTriangles(cache, &s);
  CopyPositions(cache, &s);
  s.seq = frame.seq();
  s.sim_time_s = frame.sim_time_s();
  s.current_layer = frame.current_layer();
  s.tip_depth_m = frame.tip_depth_m();
  s.paused = frame.paused();
  const auto& tool = frame.tool();
  s.tool.valid = tool.tip_m_size() == 3;
  if (s.tool.valid) {
    s.tool.tip_m = Eigen::Vector3d(tool.tip_m(0), tool.tip_m(1), tool.tip_m(2));
    s.tool.orientation = tool.orientation_wxyz_size() == 4
                             ? Eigen::Quaterniond(tool.orientation_wxyz(0), tool.orientation_wxyz(1),
                                                  tool.orientation_wxyz(2), tool.orientation_wxyz(3))
                             : Eigen::Quaterniond::Identity();
    if (s.tool.orientation.norm() < 1e-9) s.tool.orientation = Eigen::Quaterniond::Identity();
    s.tool.orientation.normalize();
  }
  // The force comes with or without a pose (none streams: the scene's force, 0).
  s.tool.force_N = tool.force_n_size() == 3 ? Eigen::Vector3d(tool.force_n(0), tool.force_n(1), tool.force_n(2))
                                            : Eigen::Vector3d::Zero();
  s.tool.contact_state = tool.contact_state();
  for (const auto& e : frame.events()) {
    if (e.kind() == "reset") s.history.clear();
    EventView ev;
    ev.t_s = e.t_s();
    ev.kind = e.kind();
    ev.layer = s.LayerName(e.layer());
    ev.has_where = e.where_m_size() == 3;
    if (ev.has_where) ev.where_m = Eigen::Vector3d(e.where_m(0), e.where_m(1), e.where_m(2));
    ev.value = e.value();
    s.events.push_back(std::move(ev));
    if (s.events.size() > kMaxEvents) s.events.pop_front();
  }
  // A keyframe after a reset or re-subscription may go back in time.
  if (!s.history.empty() && frame.sim_time_s() < s.history.back().t_s) s.history.clear();
  if (s.history.size() >= kMaxHistory) s.history.erase(s.history.begin(), s.history.begin() + kMaxHistory / 4);
  // The 1 kHz peak since the previous frame, not the force at the frame's tick alone.
  s.history.push_back({frame.sim_time_s(), std::max(frame.peak_force_n(), s.tool.force_N.norm()), frame.tip_depth_m()});
  ++s.frames;
  ++s.version;
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
  *out = state_;  // the triangle list is shared, not copied
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
