// A trial driven without a server: a scene stepped by StepScene() with a
// scripted tool (a press into the tissue and back, with a pause and a
// reset), each tick handed to a SessionRecorder as a session would.
#pragma once
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hapsim/core/scenes/scene.h"
#include "hapsim/recording/recording_service.h"

namespace hapsim::service::testing {

// The tool of tick i of a scripted press: down 6 mm over 1.5 s and back up,
// with a little sideways wobble so no two poses are equal.
inline TickInput ScriptedInput(std::uint64_t tick) {
  TickInput in;
  in.tick = tick;
  const double t = static_cast<double>(tick) * 1e-3;
  const double depth_m = 0.006 * std::sin(M_PI * std::fmod(t, 3.0) / 3.0);
  in.tool.valid = tick >= 10;
  in.tool.tip_W_m = Eigen::Vector3d(0.0005 * std::sin(7.0 * t), 0.0003 * std::cos(5.0 * t), 0.002 - depth_m);
  in.tool.velocity_W_m_per_s =
      Eigen::Vector3d(0.0035 * std::cos(7.0 * t), 0.0, -0.006 * M_PI / 3.0 * std::cos(M_PI * std::fmod(t, 3.0) / 3.0));
  in.device_id = 7;
  in.pose_seq = tick / 2;
  in.fresh_pose = tick % 2 == 0;
  return in;
}

// A scratch directory removed at the end of the test.
struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& name) {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("hapsim-rec-" + name + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() { std::filesystem::remove_all(path); }
};

inline RecordedSession TestSession(const std::string& scene = "tissue_block") {
  RecordedSession who;
  who.session_id = "t1";
  who.run_id = "run1";
  who.scene = scene;
  who.owner = "alice";
  who.class_name = "acu-101";
  return who;
}

// Runs ticks [first, first + count) of the script on `scene`, through the
// recorder like a session's tick; `reset_at` ticks carry a reset and
// `paused_from`..`paused_to` are paused.
inline void RunScript(core::Scene& scene, SessionRecorder& recorder, std::uint64_t first, std::uint64_t count,
                      const std::vector<std::uint64_t>& reset_at = {}, std::uint64_t paused_from = 0,
                      std::uint64_t paused_to = 0) {
  for (std::uint64_t tick = first; tick < first + count; ++tick) {
    TickInput in = ScriptedInput(tick);
    for (auto r : reset_at) in.reset = in.reset || r == tick;
    in.paused = tick >= paused_from && tick < paused_to;
    StepScene(scene, in, 1e-3);
    recorder.OnTick(TickOutcome{in, scene, scene.ForceModel().state, scene.ToolForce_W_N().norm()});
  }
}

inline std::vector<std::filesystem::path> FilesUnder(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace hapsim::service::testing
