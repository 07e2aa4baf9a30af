// hapsim-viewer's picture mode: a window (GLFW) or an off-screen context
// (EGL, --headless with --png/--plot-png/--benchmark-seconds) showing one
// session's mesh with ImGui panels — connection, tool state, live force
// plots, events, the controls the caller's role allows — and, with a class
// name, the instructor's console of every session of the class.
#pragma once
#include <optional>
#include <string>

#include "hapsim/gui/orbit_camera.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/viewer_client.h"

namespace hapsim::gui {

struct GuiOptions {
  viewer::Connection connection;
  viewer::ViewerOptions viewer;  // session (empty with a class: its first session once listed), name, rate, ack window
  std::string class_name;           // the instructor's class console ("" none)
  double class_rate_hz = 10.0;
  std::string open_trial;           // with a class: the recorded trial to open as a replay ("latest": the newest ended)
  std::string replay_path;          // play a recording instead of a server stream
  std::string record_path;          // record the stream here
  std::string png_path;             // the last frame as a picture
  std::string plot_png_path;        // the force-depth and force-time plots as a picture
  std::string obj_path;             // the final mesh as OBJ (as the headless viewer writes it)
  std::string export_path;          // the final mesh by extension: .obj .gltf .glb .vtk
  bool headless = false;            // off-screen (EGL): no display needed. Pictures asked for without a
                                    // display are drawn off screen too.
  bool panels = true;
  bool vsync = true;
  double max_fps = 60.0;  // a window draws on change, at most this often
  int width_px = 1280, height_px = 720;
  double seconds = 0.0;             // stop after this long (0: until closed)
  std::uint64_t frames = 0;         // stop after this many frames received (0: no limit)
  double benchmark_seconds = 0.0;   // render flat out this long, re-uploading positions every frame; print fps
  std::optional<CameraPose> camera; // fixed camera (else fitted to the mesh)
  bool follow_tool = false;
  RenderOptions render;             // what is drawn (tool, force arrow, see-through layers, markers)
};

// Returns the process exit code: 0, 1 (runtime failure: no GL, unreadable
// recording, unwritable picture), 2 (bad use).
int RunViewerGui(const GuiOptions& options);

}  // namespace hapsim::gui
