// What a session hands to the frame pump at the viewer frame rate: a copy of
// the displayed scene at one instant. Immutable once published; shared by
// every viewer stream of the session. Every array is sized at session
// creation (the scene's vertex and triangle capacities), so publishing one
// copies and never allocates.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/mesh/topology_log.h"
#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

struct SceneSnapshot {
  std::uint64_t id = 0;  // increases by one per snapshot of this session
  double sim_time_s = 0.0;
  bool paused = false;

  // Whether the mesh fields below are this instant's. Copying a mesh at the
  // frame rate costs the tick worker (~12 µs for acupuncture's 5 056
  // vertices), and only viewers and GetSnapshot read it: a session nobody
  // watches publishes snapshots without it (Session::WantMeshUntil), whose
  // mesh fields are then an older fill of the reused buffer, not to be read.
  bool has_mesh = true;

  // The mesh in slots. Only slots below vertex_slots / triangle_slots and
  // live are meaningful.
  Eigen::Matrix3Xd vertices_m;  // 3 x vertex capacity [m]
  std::uint32_t vertex_slots = 0;
  std::uint32_t triangle_slots = 0;
  std::vector<std::uint8_t> vertex_live;                   // (vertex capacity)
  std::vector<std::array<std::uint32_t, 3>> triangles;     // (triangle capacity)
  std::vector<std::uint16_t> triangle_parts;               // (triangle capacity)
  std::vector<std::uint8_t> triangle_live;                 // (triangle capacity)
  std::uint64_t topology_version = 0;
  // The topology arrays above hold this version (a reused buffer is
  // re-copied only when the topology changed since it was last filled).
  std::uint64_t topology_arrays_version = ~std::uint64_t{0};
  // Edits [edits_from_version, topology_version) of the scene's log: the
  // ones the frame pump has not taken yet. If edits_from_version is above
  // what the pump has, edits were lost (log wrapped, reset): keyframes.
  std::uint64_t edits_from_version = 0;
  std::vector<core::TopologyEdit> topology_edits;          // reserved to the log capacity
  std::shared_ptr<const std::vector<std::string>> part_names;   // fixed per session
  std::shared_ptr<const std::vector<std::string>> layer_names;  // fixed per session

  core::ToolInput tool;
  Eigen::Vector3d tool_force_W_N = Eigen::Vector3d::Zero();
  core::ContactState contact = core::ContactState::kFree;
  int current_layer = -1;
  double tip_depth_m = 0.0;
  // The scene's most recent events and how many events it has logged in
  // total, so each stream can send exactly the ones it has not sent yet.
  std::vector<core::SceneEvent> recent_events;
  std::uint64_t events_total = 0;

  // The peak |tool force| of each of the last kPeakIntervals snapshot
  // intervals (the ticks after the previous snapshot, up to this one's):
  // interval_peak_N[k % kPeakIntervals] belongs to snapshot id k. A frame
  // carries the peak over the ticks since its stream's previous frame
  // (PeakForceSince), so a 60 Hz plot shows the 1 kHz peaks.
  static constexpr std::uint64_t kPeakIntervals = 64;
  std::array<double, kPeakIntervals> interval_peak_N{};
};

// The peak |tool force| over the ticks after snapshot previous_id up to
// snapshot s (previous_id 0: this interval only; an interval older than
// the kept ones: all kept, about 1 s at 60 Hz).
double PeakForceSince(const SceneSnapshot& s, std::uint64_t previous_id);

// Copies a scene's mesh into a snapshot buffer sized for it (SnapshotRing):
// positions, the slot arrays (only if the buffer holds an older topology
// version) and the log's edits from `taken_version` on (or from the log's
// oldest, if it no longer reaches back that far). Never allocates.
void CopyMesh(const Eigen::Matrix3Xd& vertices_m, const core::MeshTopology& topology, std::uint64_t taken_version,
              SceneSnapshot* snapshot);

}  // namespace hapsim::service
