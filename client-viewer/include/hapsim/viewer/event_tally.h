// What happened to the tissue over a stream, tallied from decoded frames:
// events per kind, the punctures in order (which layer, how deep), the
// incisions' lengths and the frames that changed the topology (cuts). The
// headless viewer prints it at the end; the stream client itself knows
// nothing of scenes.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hapsim/viewer/viewer_frame.h"

namespace hapsim::viewer {

struct Puncture {
  std::string layer;      // its name, or "layerN" for an index the keyframe does not name
  double depth_mm = 0.0;  // of the tip below the top surface at z = 0, at the puncture instant
};

struct EventTally {
  std::array<std::uint64_t, kEventKindCount> counts{};  // per EventKind
  std::vector<Puncture> punctures;                      // in order
  std::vector<double> incisions_mm;                     // each kCutEnd's incision length, in order
  std::uint64_t topology_frames = 0;                    // frames that carried topology edits

  // Every frame read counts, including one whose mesh was refused.
  void Add(const ViewerFrame& frame);
  std::uint64_t count(EventKind kind) const { return counts[static_cast<std::size_t>(kind)]; }
};

}  // namespace hapsim::viewer
