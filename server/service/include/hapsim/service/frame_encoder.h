// Builds one viewer stream's frames from session snapshots: a keyframe first
// (and after any topology change or resync request), then deltas holding only
// the vertices whose quantised position changed since the previous frame *of
// this stream*. Because a delta is always relative to what this stream last
// sent, skipped (coalesced) snapshots never break the chain and seqs stay
// contiguous.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hapsim/service/scene_snapshot.h"
#include "hapsim/v1/viewer.pb.h"

namespace hapsim::service {

struct StreamEncoderState {
  double quantum_m = 1e-5;        // position quantisation step (10 µm)
  bool need_keyframe = true;
  std::uint64_t next_seq = 0;
  std::uint64_t topology_version = 0;
  std::vector<std::int32_t> sent_q;  // 3 per vertex: what the viewer holds
  std::uint64_t events_sent = 0;     // SceneSnapshot::events_total already sent
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

// Fills *frame (cleared first) and advances *state.
void EncodeFrame(const SceneSnapshot& snapshot, StreamEncoderState* state, hapsim::v1::Frame* frame);

}  // namespace hapsim::service
