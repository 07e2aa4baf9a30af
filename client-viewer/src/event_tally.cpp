#include "hapsim/viewer/event_tally.h"

namespace hapsim::viewer {

void EventTally::Add(const ViewerFrame& frame) {
  if (frame.topology_edits) ++topology_frames;
  for (const FrameEvent& e : frame.events) {
    ++counts[static_cast<std::size_t>(e.kind)];
    if (e.kind == EventKind::kCutEnd) incisions_mm.push_back(1e3 * e.value);
    if (e.kind == EventKind::kPuncture) {
      // The event's own position: the tip at the puncture instant.
      const double z_m = e.has_where ? e.where_m.z() : 0.0;
      punctures.push_back({e.layer.empty() ? "layer" + std::to_string(e.layer_index) : e.layer, -z_m * 1e3});
    }
  }
}

}  // namespace hapsim::viewer
