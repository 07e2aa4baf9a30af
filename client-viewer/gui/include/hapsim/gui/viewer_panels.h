// The viewer's ImGui panels: the session's state and controls, live force
// plots (vs time, and vs depth — the acupuncture paper's curve, drawn as it
// happens), the event list, and the instructor's class console.
#pragma once
#include <future>
#include <memory>
#include <string>

#include "hapsim/gui/class_board.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/past_trials.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/viewer/session_client.h"

namespace hapsim::gui {

// Pause / resume / reset sent off the render thread; the answer (or the
// server's refusal, e.g. PERMISSION_DENIED for an observer) is shown.
class SessionControls {
 public:
  explicit SessionControls(const viewer::Connection& connection);
  void Send(viewer::SessionClient::Control control, const std::string& session_id);
  const std::string& last_result();  // "" until an answer came
  bool busy();

 private:
  std::unique_ptr<viewer::SessionClient> client_;
  std::string init_error_;
  std::future<std::string> pending_;
  std::string last_;
};

struct ViewState {
  RenderOptions render;
  bool follow_tool = false;
  bool reset_view = false;  // set by the panel's button (or R): the app refits the camera
  std::size_t mesh_triangles = 0, drawn_triangles = 0;  // from the renderer, for the panel
};

struct StreamRate {  // frames per second of the stream, over ~1 s
  double fps = 0.0;
  double last_time_s = -1.0;
  std::uint64_t last_frames = 0;
  double since_frame_s = 0.0;  // wall time since the last new frame
  std::uint64_t seen_version = 0;
  void Update(const SceneView& scene, double now_s, double dt_s);
};

void DrawSessionPanel(const SceneView& scene, const std::string& session_id, const std::string& server,
                      const StreamRate& rate, ViewState* view, SessionControls* controls);
void DrawForcePlots(const SceneView& scene, float width_px, float plot_height_px);
// The force plots' |F| axis tops 10 % above the peak shown, and at least at
// 1.1 x kMinForceAxis_N: a vein pressed with 0.05 N fills its plot (a fixed
// 0.5 N floor drew it as a line along the axis), a free tool's noise does not.
inline constexpr double kMinForceAxis_N = 0.01;
double ForceAxisTop_N(double peak_N);
void DrawEventList(const SceneView& scene);
// How the class console lays its tiles out in avail_px of width with
// spacing_px between tiles: as many columns as fit tiles of at least
// kMinTileWidth_px, the tiles widened to fill the row.
struct TileGrid {
  static constexpr float kMinTileWidth_px = 240.0f;
  int columns = 1;
  float tile_width_px = kMinTileWidth_px;
};
TileGrid ClassTileGrid(float avail_px, float spacing_px);

// Tiles of every session of the class; returns the id the instructor
// clicked to watch ("" when none was clicked).
std::string DrawClassConsole(const ClassView& view, const std::string& watched, SessionControls* controls);

// The console's past trials (past_trials_panel.cpp): the class's recorded
// trials with an Open button each, and the open replay's progress against
// its recorded state hashes with play/pause, step, a seek slider and close.
// Returns the replay session to watch when its Watch button was clicked ("").
struct PastTrialsPanel {
  float seek_s = 0.0f;  // the slider while dragged
  bool dragging = false;
};
std::string DrawPastTrials(const PastTrials::View& view, const std::string& watched, PastTrials* past,
                           PastTrialsPanel* panel);

}  // namespace hapsim::gui
