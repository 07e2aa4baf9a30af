#include "hapsim/streaming/frame_encoder.h"

#include <cmath>
#include <limits>

namespace hapsim::service {

namespace {

void FillCommon(const SceneSnapshot& s, hapsim::v1::Frame* frame) {
  frame->set_sim_time_s(s.sim_time_s);
  frame->set_topology_version(s.topology_version);
  frame->set_current_layer(s.current_layer);
  frame->set_tip_depth_m(s.tip_depth_m);
  frame->set_paused(s.paused);
  auto* tool = frame->mutable_tool();
  if (s.tool.valid) {  // a device streams: where its tool is (else no pose: nothing to draw)
    for (int i = 0; i < 3; ++i) tool->add_tip_m(s.tool.tip_W_m[i]);
    tool->add_orientation_wxyz(s.tool.orientation_W.w());
    tool->add_orientation_wxyz(s.tool.orientation_W.x());
    tool->add_orientation_wxyz(s.tool.orientation_W.y());
    tool->add_orientation_wxyz(s.tool.orientation_W.z());
  }
  for (int i = 0; i < 3; ++i) tool->add_force_n(s.tool_force_W_N[i]);
  tool->set_contact_state(core::ToString(s.contact));
}

}  // namespace

void EncodeEvent(const core::SceneEvent& e, hapsim::v1::SceneEvent* out) {
  out->set_t_s(e.t_s);
  out->set_kind(core::ToString(e.kind));
  out->set_layer(e.layer);
  for (int k = 0; k < 3; ++k) out->add_where_m(e.where_W_m[k]);
  out->set_value(e.value);
}

std::uint64_t AppendEventsSince(const SceneSnapshot& s, std::uint64_t events_sent,
                                google::protobuf::RepeatedPtrField<hapsim::v1::SceneEvent>* out) {
  const std::uint64_t unsent = s.events_total > events_sent ? s.events_total - events_sent : 0;
  const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(unsent, s.recent_events.size()));
  for (std::size_t i = s.recent_events.size() - n; i < s.recent_events.size(); ++i) {
    EncodeEvent(s.recent_events[i], out->Add());
  }
  return s.events_total;
}

namespace {

void EncodeKeyframe(const SceneSnapshot& s, StreamEncoderState* state, hapsim::v1::Frame* frame) {
  const auto capacity = static_cast<std::size_t>(s.vertices_m.cols());
  state->sent_q.assign(3 * capacity, 0);
  auto* key = frame->mutable_keyframe();
  key->set_quantum_m(state->quantum_m);
  key->set_vertex_capacity(static_cast<std::uint32_t>(capacity));
  key->set_triangle_capacity(static_cast<std::uint32_t>(s.triangles.size()));
  key->mutable_positions_q()->Reserve(static_cast<int>(3 * s.vertex_slots));
  for (std::uint32_t v = 0; v < s.vertex_slots; ++v) {
    if (!s.vertex_live[v]) {
      key->add_free_vertices(v);
      for (int k = 0; k < 3; ++k) key->add_positions_q(0);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const std::int32_t q = QuantiseCoordinate(s.vertices_m(k, static_cast<Eigen::Index>(v)), state->quantum_m);
      state->sent_q[3 * v + static_cast<std::size_t>(k)] = q;
      key->add_positions_q(q);
    }
  }
  key->mutable_triangles()->Reserve(static_cast<int>(3 * s.triangle_slots));
  for (std::uint32_t t = 0; t < s.triangle_slots; ++t) {
    if (!s.triangle_live[t]) {
      key->add_free_triangles(t);
      for (int k = 0; k < 3; ++k) key->add_triangles(0);
      key->add_triangle_parts(0);
      continue;
    }
    for (const std::uint32_t v : s.triangles[t]) key->add_triangles(v);
    key->add_triangle_parts(s.triangle_parts[t]);
  }
  if (s.part_names) {
    for (const auto& name : *s.part_names) key->add_part_names(name);
  }
  if (s.layer_names) {
    for (const auto& name : *s.layer_names) key->add_layer_names(name);
  }
}

// The edits [state->topology_version, s.topology_version) from the history;
// a vertex added here starts at q = 0 on both sides, so the position delta
// that follows carries its absolute position.
void EncodeTopology(const SceneSnapshot& s, const TopologyHistory& history, StreamEncoderState* state,
                    hapsim::v1::Frame* frame) {
  auto* topo = frame->mutable_topology();
  topo->set_from_version(state->topology_version);
  auto* edits = topo->mutable_edits();
  for (std::uint64_t v = state->topology_version; v < s.topology_version; ++v) {
    const core::TopologyEdit& e = history.At(v);
    AppendEdit(e, edits);
    if (e.kind == core::TopologyEdit::Kind::kAddVertex) {
      for (int k = 0; k < 3; ++k) state->sent_q[3 * e.slot + static_cast<std::size_t>(k)] = 0;
    }
  }
}

void EncodePositions(const SceneSnapshot& s, StreamEncoderState* state, hapsim::v1::Frame* frame) {
  auto* delta = frame->mutable_delta();
  std::uint32_t previous_index = 0;
  bool first = true;
  for (std::uint32_t v = 0; v < s.vertex_slots; ++v) {
    if (!s.vertex_live[v]) continue;
    std::int32_t q[3];
    bool moved = false;
    for (int k = 0; k < 3; ++k) {
      q[k] = QuantiseCoordinate(s.vertices_m(k, static_cast<Eigen::Index>(v)), state->quantum_m);
      moved |= q[k] != state->sent_q[3 * v + static_cast<std::size_t>(k)];
    }
    if (!moved) continue;
    delta->add_index_gaps(first ? v : v - previous_index);
    first = false;
    previous_index = v;
    for (int k = 0; k < 3; ++k) {
      std::int32_t& sent = state->sent_q[3 * v + static_cast<std::size_t>(k)];
      // 64-bit difference, then narrowed: saturated coordinates stay in range.
      delta->add_position_dq(static_cast<std::int32_t>(static_cast<std::int64_t>(q[k]) - sent));
      sent = q[k];
    }
  }
}

}  // namespace

void AppendEdit(const core::TopologyEdit& e, google::protobuf::RepeatedField<std::uint32_t>* out) {
  out->Add(static_cast<std::uint32_t>(e.kind));
  out->Add(e.slot);
  if (e.kind == core::TopologyEdit::Kind::kAddTriangle) {
    out->Add(e.part);
    for (const std::uint32_t v : e.vertices) out->Add(v);
  }
}

void EncodeFrame(const SceneSnapshot& s, const TopologyHistory& history, StreamEncoderState* state,
                 hapsim::v1::Frame* frame) {
  frame->Clear();
  const bool topology_changed = s.topology_version != state->topology_version;
  if (state->sent_q.size() != 3 * static_cast<std::size_t>(s.vertices_m.cols()) ||
      (topology_changed && !history.Covers(state->topology_version, s.topology_version))) {
    state->need_keyframe = true;
  }
  frame->set_seq(state->next_seq++);
  FillCommon(s, frame);
  frame->set_peak_force_n(std::max(PeakForceSince(s, state->snapshot_id), s.tool_force_W_N.norm()));
  state->snapshot_id = s.id;
  state->events_sent = AppendEventsSince(s, state->events_sent, frame->mutable_events());
  if (state->need_keyframe) {
    state->need_keyframe = false;
    EncodeKeyframe(s, state, frame);
  } else {
    if (topology_changed) EncodeTopology(s, history, state, frame);
    EncodePositions(s, state, frame);
  }
  state->topology_version = s.topology_version;
}

}  // namespace hapsim::service
