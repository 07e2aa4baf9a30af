// What a session hands to the frame pump at the viewer frame rate: a copy of
// the displayed scene at one instant. Immutable once published; shared by
// every viewer stream of the session (topology arrays are shared pointers and
// only replaced when the topology version changes).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/core/scenes/scene.h"

namespace hapsim::service {

struct SceneSnapshot {
  std::uint64_t id = 0;  // increases by one per snapshot of this session
  double sim_time_s = 0.0;
  bool paused = false;
  Eigen::Matrix3Xd vertices_m;  // 3 x n
  std::uint64_t topology_version = 0;
  std::shared_ptr<const std::vector<std::uint32_t>> triangles;
  std::shared_ptr<const std::vector<core::SurfacePart>> parts;
  std::shared_ptr<const std::vector<std::string>> layer_names;
  core::ToolInput tool;
  Eigen::Vector3d tool_force_W_N = Eigen::Vector3d::Zero();
  core::ContactState contact = core::ContactState::kFree;
  int current_layer = -1;
  double tip_depth_m = 0.0;
  // The scene's most recent events and how many events it has logged in
  // total, so each stream can send exactly the ones it has not sent yet.
  std::vector<core::SceneEvent> recent_events;
  std::uint64_t events_total = 0;
};

}  // namespace hapsim::service
