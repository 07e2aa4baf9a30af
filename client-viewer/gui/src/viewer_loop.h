// The picture mode's loop, one step per method: take the newest state of
// the stream (or replay), wait for something worth drawing (a window draws
// on change, at most max_fps), draw panels and scene, and at the end write
// the pictures. RunViewerGui (viewer_app.cpp) opens the GL surface and ImGui
// around it.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "hapsim/gui/class_board.h"
#include "hapsim/gui/frame_replay.h"
#include "hapsim/gui/gl_context.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/orbit_camera.h"
#include "hapsim/gui/past_trials.h"
#include "hapsim/gui/redraw_policy.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/gui/stream_worker.h"
#include "hapsim/gui/viewer_app.h"
#include "hapsim/gui/viewer_panels.h"
#include "hapsim/viewer/frame_log.h"

struct GLFWwindow;
struct ImGuiIO;

namespace hapsim::gui {

// SIGINT/SIGTERM end the loop like closing the window (pictures are still written).
void CatchStopSignals();
// Any input to the window makes a redraw due. Install before ImGui's GLFW
// backend, which chains to these callbacks.
void WatchWindowInput(GLFWwindow* window);

// Where the pictures go: a window, or an off-screen framebuffer.
struct GlSurface {
  std::unique_ptr<GlWindow> window;
  std::unique_ptr<HeadlessGl> headless;
};

class ViewerLoop {
 public:
  // Everything is borrowed and outlives the loop; ImGui and a GL context are current.
  ViewerLoop(const GuiOptions& options, const GlSurface& surface, viewer::FrameLogWriter* recorder,
             FrameReplay* replay);
  // False with *error when the renderer cannot be made (shaders).
  bool Start(std::string* error);
  // Until the window closes, a limit or a signal; false when a picture could not be written.
  bool Run();
  void PrintSummary();
  // Stops the stream and returns the mesh it (or the replay) left.
  std::optional<viewer::CompactMesh> TakeFinalMesh();
  const std::string& watched() const { return watched_; }
  // Drops the GL objects and threads before the context goes.
  void Release();

 private:
  using Clock = std::chrono::steady_clock;

  void Watch(const std::string& session);
  void PickFirstSession();
  void FollowPastTrials();  // watches a replay once opened; keeps its progress fresh
  bool PollWindow();  // false when the window was closed
  bool TimeUp(double elapsed_s) const;
  bool DueForDraw(double elapsed_s);
  void WaitForFrames();
  void DrawFrame(bool plots_only);
  void BeginImGuiFrame(double dt_s);
  void DrawPlotsOnly();
  void DrawPanels(int panel_w);
  void UpdateCamera();
  void Render(bool plots_only, int panel_w);
  void WritePictures();
  void PrintBenchmark();

  const GuiOptions& options_;
  const GlSurface& surface_;
  viewer::FrameLogWriter* recorder_;
  FrameReplay* replay_;
  ImGuiIO& io_;
  const bool replaying_, console_;
  const bool still_;  // off screen without a benchmark: one picture at the end
  const bool paced_;  // a window draws on change at most max_fps (a benchmark draws flat out)

  LiveScene live_;
  std::unique_ptr<SceneRenderer> renderer_;
  std::string watched_;
  bool picked_first_ = false;
  std::unique_ptr<StreamWorker> stream_;
  std::unique_ptr<ClassBoard> board_;
  std::unique_ptr<SessionControls> controls_;
  std::unique_ptr<PastTrials> past_;
  PastTrials::View past_view_;
  PastTrialsPanel past_panel_;
  Clock::time_point past_polled_;

  OrbitCamera camera_;
  bool fitted_ = false;
  ViewState view_;
  StreamRate rate_;
  SceneView scene_;
  RedrawPolicy redraw_;
  std::uint64_t board_updates_ = 0;
  bool pending_change_ = false;  // a new frame or board update not drawn yet
  int width_ = 0, height_ = 0;
  Clock::time_point start_, last_, first_drawn_;  // the benchmark counts from the first frame drawn
  std::uint64_t drawn_ = 0, drawn_with_mesh_ = 0;
  double render_s_ = 0.0;
  bool ok_ = true;
};

}  // namespace hapsim::gui
