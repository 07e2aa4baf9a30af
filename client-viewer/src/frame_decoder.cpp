#include "hapsim/viewer/frame_decoder.h"

#include <algorithm>

namespace hapsim::viewer {

namespace {

Eigen::Vector3d DecodeVector3(const google::protobuf::RepeatedField<double>& v) {
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

void DecodeTool(const hapsim::v1::ToolState& wire, FrameTool* tool) {
  tool->valid = wire.tip_m_size() == 3;
  tool->tip_m = tool->valid ? DecodeVector3(wire.tip_m()) : Eigen::Vector3d::Zero();
  tool->orientation = Eigen::Quaterniond::Identity();
  if (tool->valid && wire.orientation_wxyz_size() == 4) {
    const auto& q = wire.orientation_wxyz();
    const Eigen::Quaterniond orientation(q[0], q[1], q[2], q[3]);
    if (orientation.norm() >= 1e-9) tool->orientation = orientation.normalized();  // else no usable rotation
  }
  tool->force_N = wire.force_n_size() == 3 ? DecodeVector3(wire.force_n()) : Eigen::Vector3d::Zero();
  tool->contact_state = wire.contact_state();
}

// "" for no layer or an index past the names.
std::string DecodeLayerName(const hapsim::v1::Frame& wire, const MeshCache& mesh, int layer) {
  if (layer < 0) return {};
  if (wire.has_keyframe()) {
    const auto& names = wire.keyframe().layer_names();
    return layer < names.size() ? names[layer] : std::string();
  }
  const auto& names = mesh.layer_names();
  return static_cast<std::size_t>(layer) < names.size() ? names[static_cast<std::size_t>(layer)] : std::string();
}

void DecodeEvent(const hapsim::v1::SceneEvent& wire, std::string layer_name, FrameEvent* event) {
  event->t_s = wire.t_s();
  event->kind = ParseEventKind(wire.kind());
  event->layer_index = wire.layer();
  event->layer = std::move(layer_name);
  event->has_where = wire.where_m_size() == 3;
  event->where_m = event->has_where ? DecodeVector3(wire.where_m()) : Eigen::Vector3d::Zero();
  event->value = wire.value();
}

}  // namespace

void DecodeFrame(const hapsim::v1::Frame& wire, const MeshCache& mesh, ViewerFrame* out) {
  out->seq = wire.seq();
  out->topology_version = wire.topology_version();
  out->sim_time_s = wire.sim_time_s();
  out->paused = wire.paused();
  out->keyframe = wire.has_keyframe();
  out->topology_edits = wire.has_topology();
  out->moved_vertices = wire.has_delta() ? static_cast<std::size_t>(wire.delta().index_gaps_size()) : 0;
  DecodeTool(wire.tool(), &out->tool);
  out->current_layer = wire.current_layer();
  out->tip_depth_m = wire.tip_depth_m();
  out->peak_force_N = std::max(wire.peak_force_n(), out->tool.force_N.norm());
  out->events.resize(static_cast<std::size_t>(wire.events_size()));
  for (int i = 0; i < wire.events_size(); ++i) {
    const auto& event = wire.events(i);
    DecodeEvent(event, DecodeLayerName(wire, mesh, event.layer()), &out->events[static_cast<std::size_t>(i)]);
  }
}

const ViewerFrame& FrameDecoder::Decode(const hapsim::v1::Frame& wire) {
  DecodeFrame(wire, mesh_, &frame_);
  return frame_;
}

}  // namespace hapsim::viewer
