#include "hapsim/service/frame_encoder.h"

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
  for (int i = 0; i < 3; ++i) tool->add_tip_m(s.tool.tip_W_m[i]);
  tool->add_orientation_wxyz(s.tool.orientation_W.w());
  tool->add_orientation_wxyz(s.tool.orientation_W.x());
  tool->add_orientation_wxyz(s.tool.orientation_W.y());
  tool->add_orientation_wxyz(s.tool.orientation_W.z());
  for (int i = 0; i < 3; ++i) tool->add_force_n(s.tool_force_W_N[i]);
  tool->set_contact_state(core::ToString(s.contact));
}

void FillEvents(const SceneSnapshot& s, StreamEncoderState* state, hapsim::v1::Frame* frame) {
  const std::uint64_t unsent = s.events_total > state->events_sent ? s.events_total - state->events_sent : 0;
  const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(unsent, s.recent_events.size()));
  for (std::size_t i = s.recent_events.size() - n; i < s.recent_events.size(); ++i) {
    const core::SceneEvent& e = s.recent_events[i];
    auto* out = frame->add_events();
    out->set_t_s(e.t_s);
    out->set_kind(core::ToString(e.kind));
    out->set_layer(e.layer);
    for (int k = 0; k < 3; ++k) out->add_where_m(e.where_W_m[k]);
  }
  state->events_sent = s.events_total;
}

}  // namespace

void EncodeFrame(const SceneSnapshot& s, StreamEncoderState* state, hapsim::v1::Frame* frame) {
  frame->Clear();
  const auto n_vertices = static_cast<std::size_t>(s.vertices_m.cols());
  if (s.topology_version != state->topology_version || state->sent_q.size() != 3 * n_vertices) {
    state->need_keyframe = true;
  }
  frame->set_seq(state->next_seq++);
  FillCommon(s, frame);
  FillEvents(s, state, frame);

  if (state->need_keyframe) {
    state->need_keyframe = false;
    state->topology_version = s.topology_version;
    state->sent_q.resize(3 * n_vertices);
    auto* key = frame->mutable_keyframe();
    key->set_quantum_m(state->quantum_m);
    key->mutable_positions_q()->Reserve(static_cast<int>(3 * n_vertices));
    for (std::size_t v = 0; v < n_vertices; ++v) {
      for (int k = 0; k < 3; ++k) {
        const std::int32_t q = QuantiseCoordinate(s.vertices_m(k, static_cast<Eigen::Index>(v)), state->quantum_m);
        state->sent_q[3 * v + static_cast<std::size_t>(k)] = q;
        key->add_positions_q(q);
      }
    }
    if (s.triangles) key->mutable_triangles()->Add(s.triangles->begin(), s.triangles->end());
    if (s.parts) {
      for (const auto& p : *s.parts) {
        auto* part = key->add_parts();
        part->set_name(p.name);
        part->set_first_triangle(p.first_triangle);
        part->set_triangle_count(p.triangle_count);
      }
    }
    if (s.layer_names) {
      for (const auto& name : *s.layer_names) key->add_layer_names(name);
    }
    return;
  }

  auto* delta = frame->mutable_delta();
  std::uint32_t previous_index = 0;
  bool first = true;
  for (std::size_t v = 0; v < n_vertices; ++v) {
    std::int32_t q[3];
    bool moved = false;
    for (int k = 0; k < 3; ++k) {
      q[k] = QuantiseCoordinate(s.vertices_m(k, static_cast<Eigen::Index>(v)), state->quantum_m);
      moved |= q[k] != state->sent_q[3 * v + static_cast<std::size_t>(k)];
    }
    if (!moved) continue;
    const auto index = static_cast<std::uint32_t>(v);
    delta->add_index_gaps(first ? index : index - previous_index);
    first = false;
    previous_index = index;
    for (int k = 0; k < 3; ++k) {
      std::int32_t& sent = state->sent_q[3 * v + static_cast<std::size_t>(k)];
      // 64-bit difference, then narrowed: saturated coordinates stay in range.
      delta->add_position_dq(static_cast<std::int32_t>(static_cast<std::int64_t>(q[k]) - sent));
      sent = q[k];
    }
  }
}

}  // namespace hapsim::service
