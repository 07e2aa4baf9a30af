// Builds one viewer stream's frames from session snapshots: a keyframe first,
// then deltas. A delta carries the topology edits since the version this
// stream last sent (from the session's TopologyHistory) and then only the
// live vertices whose quantised position changed since the previous frame
// *of this stream*. Because a delta is always relative to what this stream
// last sent, skipped (coalesced) snapshots never break the chain and seqs
// stay contiguous. A keyframe is sent again only when the history no longer
// holds the stream's version (it wrapped, or the scene was reset).
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hapsim/runtime/scene_snapshot.h"
#include "hapsim/streaming/topology_history.h"
#include "hapsim/v1/viewer.pb.h"

namespace hapsim::service {

struct StreamEncoderState {
  double quantum_m = 1e-5;        // position quantisation step (10 µm)
  bool need_keyframe = true;
  std::uint64_t next_seq = 0;
  std::uint64_t topology_version = 0;
  std::vector<std::int32_t> sent_q;  // 3 per vertex slot: what the viewer holds
  std::uint64_t events_sent = 0;     // SceneSnapshot::events_total already sent
  std::uint64_t snapshot_id = 0;     // of the last frame sent (0: none yet)
};

// Quantise a coordinate [m] to the nearest multiple of quantum_m (saturating;
// NaN maps to the maximum). Inline: it runs for every coordinate of every frame.
inline std::int32_t QuantiseCoordinate(double x_m, double quantum_m) {
  const double q = std::nearbyint(x_m / quantum_m);
  constexpr double kMax = std::numeric_limits<std::int32_t>::max();
  if (!(q < kMax)) return std::numeric_limits<std::int32_t>::max();
  if (q < -kMax) return -std::numeric_limits<std::int32_t>::max();
  return static_cast<std::int32_t>(q);
}

// One scene event as the wire has it.
void EncodeEvent(const core::SceneEvent& event, hapsim::v1::SceneEvent* out);

// Appends the snapshot's events after the first `events_sent` the stream has
// already sent (as many as the snapshot still holds) and returns the new
// count sent (a viewer stream's frames).
std::uint64_t AppendEventsSince(const SceneSnapshot& snapshot, std::uint64_t events_sent,
                                google::protobuf::RepeatedPtrField<hapsim::v1::SceneEvent>* out);

// Fills *frame (cleared first) and advances *state. `history` must have
// absorbed the snapshot (it ends at or after snapshot.topology_version).
void EncodeFrame(const SceneSnapshot& snapshot, const TopologyHistory& history, StreamEncoderState* state,
                 hapsim::v1::Frame* frame);

// The packed edit stream of TopologyDelta.edits (docs/protocol.md):
//   add vertex [0, slot]; remove vertex [1, slot];
//   add triangle [2, slot, part, a, b, c]; remove triangle [3, slot].
void AppendEdit(const core::TopologyEdit& edit, google::protobuf::RepeatedField<std::uint32_t>* out);

}  // namespace hapsim::service
