#include "hapsim/gui/viewer_app.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <spdlog/spdlog.h>

#include "hapsim/gui/class_board.h"
#include "hapsim/gui/gl.h"
#include "hapsim/gui/gl_context.h"
#include "hapsim/gui/image.h"
#include "hapsim/gui/live_scene.h"
#include "hapsim/gui/redraw_policy.h"
#include "hapsim/gui/scene_renderer.h"
#include "hapsim/gui/stream_worker.h"
#include "hapsim/gui/viewer_panels.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_export.h"

namespace hapsim::gui {

namespace {

using Clock = std::chrono::steady_clock;

// SIGINT/SIGTERM end the window like closing it (and still write --png).
std::atomic<bool> interrupted{false};
void OnSignal(int) { interrupted = true; }
double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Set by the window's input callbacks (GLFW calls them on the render thread,
// inside glfwPollEvents/glfwWaitEventsTimeout): a redraw is due.
bool input_seen = false;

// Installed before ImGui's GLFW backend, which chains to them.
void WatchInput(GLFWwindow* window) {
  glfwSetCursorPosCallback(window, [](GLFWwindow*, double, double) { input_seen = true; });
  glfwSetMouseButtonCallback(window, [](GLFWwindow*, int, int, int) { input_seen = true; });
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double) { input_seen = true; });
  glfwSetKeyCallback(window, [](GLFWwindow*, int, int, int, int) { input_seen = true; });
  glfwSetCharCallback(window, [](GLFWwindow*, unsigned int) { input_seen = true; });
  glfwSetWindowFocusCallback(window, [](GLFWwindow*, int) { input_seen = true; });
  glfwSetCursorEnterCallback(window, [](GLFWwindow*, int) { input_seen = true; });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow*, int, int) { input_seen = true; });
  glfwSetWindowRefreshCallback(window, [](GLFWwindow*) { input_seen = true; });
}

// Plays a recording into the scene at the pace of its sim time (all at once
// for a still picture), through a MeshCache like a live stream.
class Replay {
 public:
  bool Load(const std::string& path, std::string* error) { return viewer::ReadFrameLog(path, &frames_, error); }
  std::size_t size() const { return frames_.size(); }
  // Applies every frame due by `elapsed_s` after the first one; returns false at the end.
  bool Advance(double elapsed_s, LiveScene* scene) {
    while (next_ < frames_.size()) {
      const auto& f = frames_[next_];
      if (next_ > 0 && f.sim_time_s() - frames_.front().sim_time_s() > elapsed_s) break;
      std::string why;
      const auto result = cache_.Apply(f, &why);
      if (result != viewer::ApplyResult::kApplied) {
        spdlog::warn("recorded frame {} refused ({}): {}", next_, viewer::ToString(result), why);
      } else {
        scene->OnFrame(f, cache_);
      }
      ++next_;
    }
    return next_ < frames_.size();
  }
  void ApplyAll(LiveScene* scene) { Advance(1e300, scene); }
  std::optional<viewer::CompactMesh> Mesh() const {
    return cache_.has_mesh() ? std::optional(cache_.Compact()) : std::nullopt;
  }

 private:
  std::vector<hapsim::v1::Frame> frames_;
  std::size_t next_ = 0;
  viewer::MeshCache cache_;
};

void HandleMouse(const ImGuiIO& io, OrbitCamera* camera, ViewState* view, int height_px) {
  if (io.WantCaptureMouse) return;
  const ImVec2 d = io.MouseDelta;
  if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) camera->Orbit(d.x, d.y);
  if (ImGui::IsMouseDown(ImGuiMouseButton_Right) || ImGui::IsMouseDown(ImGuiMouseButton_Middle)) {
    camera->Pan(d.x, d.y, height_px);
    view->follow_tool = false;
  }
  if (io.MouseWheel != 0.0f) camera->Zoom(io.MouseWheel);
  if (!io.WantCaptureKeyboard) {
    if (ImGui::IsKeyPressed('R')) view->reset_view = true;
    if (ImGui::IsKeyPressed('F')) view->follow_tool = !view->follow_tool;
  }
}

// Writes the final mesh where --obj/--export ask; false (with the message printed) if a file cannot be written.
bool WriteFinalMesh(const GuiOptions& options, const std::optional<viewer::CompactMesh>& mesh,
                    const std::string& session) {
  if (options.obj_path.empty() && options.export_path.empty()) return true;
  if (!mesh) {
    std::fprintf(stderr, "hapsim-viewer: no mesh arrived: nothing written to %s\n",
                 (options.obj_path.empty() ? options.export_path : options.obj_path).c_str());
    return true;  // as the headless viewer: nothing to write is not a failure of the run
  }
  const std::string comment = "hapsim session " + session;
  std::string error;
  bool ok = true;
  if (!options.obj_path.empty() && !viewer::WriteObj(options.obj_path, *mesh, comment)) {
    std::fprintf(stderr, "hapsim-viewer: cannot write %s\n", options.obj_path.c_str());
    ok = false;
  }
  if (!options.export_path.empty() && !viewer::WriteMeshFile(options.export_path, *mesh, comment, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    ok = false;
  }
  return ok;
}

}  // namespace

int RunViewerGui(const GuiOptions& options) {
  std::string error;
  std::unique_ptr<GlWindow> window;
  std::unique_ptr<HeadlessGl> headless;
  // A run that writes files (pictures, a mesh) needs no window.
  const bool writes_files = !options.png_path.empty() || !options.plot_png_path.empty() ||
                            options.benchmark_seconds > 0.0 || !options.obj_path.empty() ||
                            !options.export_path.empty();
  bool off_screen = options.headless;
  if (!off_screen) {
    window = GlWindow::Open(options.width_px, options.height_px,
                            "hapsim-viewer — " + (options.class_name.empty() ? options.viewer.session
                                                                             : "class " + options.class_name),
                            options.vsync && options.benchmark_seconds == 0.0, &error);
    if (!window && writes_files) {  // no display: what was asked for is drawn off screen
      spdlog::info("no window could be opened (no display?): drawing off screen");
      off_screen = true;
    }
  }
  if (off_screen) headless = HeadlessGl::Open(options.width_px, options.height_px, &error);
  if (!window && !headless) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 1;
  }
  std::unique_ptr<viewer::FrameLogWriter> recorder;
  if (!options.record_path.empty()) {
    recorder = std::make_unique<viewer::FrameLogWriter>();
    if (!recorder->Open(options.record_path, &error)) {
      std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
      return 1;
    }
  }
  Replay replay;
  if (!options.replay_path.empty() && !replay.Load(options.replay_path, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 1;
  }

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini dropped in the working directory
  ImGui::StyleColorsDark();
  if (window) {
    WatchInput(window->handle());
    ImGui_ImplGlfw_InitForOpenGL(window->handle(), true);
  }
  ImGui_ImplOpenGL3_Init("#version 330 core");

  LiveScene live;
  std::unique_ptr<SceneRenderer> renderer;
  try {
    renderer = std::make_unique<SceneRenderer>();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", e.what());
    return 1;
  }
  std::string watched = options.viewer.session;
  bool picked_first = false;
  std::unique_ptr<StreamWorker> stream;
  auto watch = [&](const std::string& session) {
    stream.reset();
    live.Clear();
    watched = session;
    if (!session.empty()) {
      viewer::ViewerOptions v = options.viewer;
      v.session = session;
      stream = std::make_unique<StreamWorker>(options.connection, v, &live, recorder.get());
    }
  };
  if (options.replay_path.empty()) watch(watched);
  else live.SetConnection("replay of " + options.replay_path);
  std::unique_ptr<ClassBoard> board;
  const bool console = !options.class_name.empty() && options.replay_path.empty();
  if (console) board = std::make_unique<ClassBoard>(options.connection, options.class_name, options.class_rate_hz);
  std::unique_ptr<SessionControls> controls;
  if (options.replay_path.empty()) controls = std::make_unique<SessionControls>(options.connection);

  OrbitCamera camera;
  if (options.camera) camera.pose = *options.camera;
  bool fitted = options.camera.has_value();
  ViewState view;
  view.follow_tool = options.follow_tool;
  view.render = options.render;
  StreamRate rate;
  SceneView scene;
  const auto start = Clock::now();
  auto last = start;
  std::uint64_t drawn = 0, drawn_with_mesh = 0;
  const bool still = off_screen && options.benchmark_seconds == 0.0;  // one picture at the end
  if (!options.replay_path.empty() && (still || options.benchmark_seconds > 0.0)) replay.ApplyAll(&live);
  double render_s = 0.0;
  Clock::time_point first_drawn;  // the benchmark counts from the first frame drawn

  auto draw_frame = [&](int width, int height, bool plots_only) {
    const auto now = Clock::now();
    const double dt = std::max(Seconds(now - last), 1e-4);
    last = now;
    live.CopyIfNewer(&scene);
    rate.Update(scene, Seconds(now - start), dt);
    if (options.benchmark_seconds > 0.0) ++scene.version;  // as if a delta moved every vertex each frame
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = static_cast<float>(dt);
    ImGui_ImplOpenGL3_NewFrame();
    if (window) ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const int panel_w = options.panels && !plots_only ? (console ? 540 : 380) : 0;
    if (plots_only) {
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(io.DisplaySize);
      ImGui::Begin("plots", nullptr, ImGuiWindowFlags_NoDecoration);
      ImGui::Text("session %s, sim time %.2f s, %zu samples", watched.c_str(), scene.sim_time_s, scene.history.size());
      DrawForcePlots(scene, 0.0f, (io.DisplaySize.y - 40.0f) / 2.0f);
      ImGui::End();
    } else if (panel_w > 0) {
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(static_cast<float>(panel_w), io.DisplaySize.y));
      ImGui::Begin("hapsim", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
      if (console && ImGui::CollapsingHeader("Class", ImGuiTreeNodeFlags_DefaultOpen)) {
        const std::string clicked = DrawClassConsole(board->View(), watched, controls.get());
        if (!clicked.empty() && clicked != watched) {
          watch(clicked);
          fitted = options.camera.has_value();
        }
      }
      if (!watched.empty() || !options.replay_path.empty()) {
        if (ImGui::CollapsingHeader("Session", ImGuiTreeNodeFlags_DefaultOpen))
          DrawSessionPanel(scene, options.replay_path.empty() ? watched : "(recording)",
                           options.replay_path.empty() ? options.connection.address : options.replay_path,
                           rate, &view, controls.get());
        if (ImGui::CollapsingHeader("Force", ImGuiTreeNodeFlags_DefaultOpen)) DrawForcePlots(scene, 0.0f, 150.0f);
        if (ImGui::CollapsingHeader("Events", ImGuiTreeNodeFlags_DefaultOpen)) DrawEventList(scene);
      }
      ImGui::End();
    }
    if (window) HandleMouse(io, &camera, &view, height);
    if (scene.triangles && (!fitted || view.reset_view)) {
      camera.Fit(scene.lo_m, scene.hi_m);
      fitted = true;
    }
    view.reset_view = false;
    if (view.follow_tool && scene.tool.valid) camera.pose.target_m = scene.tool.tip_m;
    ImGui::Render();
    glBindFramebuffer(GL_FRAMEBUFFER, headless ? headless->framebuffer() : 0);
    const auto render_start = Clock::now();
    if (plots_only) {  // the plots alone, on an opaque background
      glViewport(0, 0, width, height);
      glClearColor(0.06f, 0.06f, 0.06f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    } else {
      renderer->SetTriangleBudget(view.render.max_triangles);
      renderer->Upload(scene);
      view.mesh_triangles = renderer->mesh_triangles();
      view.drawn_triangles = renderer->drawn_triangles();
      renderer->Draw(scene, camera, panel_w, 0, std::max(width - panel_w, 1), height, view.render);
    }
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    render_s += Seconds(Clock::now() - render_start);
    if (drawn++ == 0) first_drawn = Clock::now();
    if (scene.triangles) ++drawn_with_mesh;
  };

  int width = options.width_px, height = options.height_px;
  bool ok = true;
  // A window draws on change at most max_fps (a benchmark draws flat out).
  const bool paced = window && options.benchmark_seconds == 0.0;
  RedrawPolicy redraw(options.max_fps);
  std::uint64_t board_updates = 0;
  bool pending_change = false;  // a new frame or board update not drawn yet
  while (true) {
    // No --session: the class's first session, once the class lists one
    // (never a session outside the class, which would be refused).
    if (console && watched.empty() && !picked_first) {
      const ClassView class_view = board->View();
      if (!class_view.sessions.empty()) {
        watch(class_view.sessions.front().status.session_id());
        picked_first = true;
      }
    }
    if (window) {
      if (paced) {  // sleep until the next draw may happen, or input comes
        const double wait = redraw.WaitBefore(Seconds(Clock::now() - start));
        if (wait > 0.0)
          glfwWaitEventsTimeout(wait);
        else
          glfwPollEvents();
      } else {
        glfwPollEvents();
      }
      if (window->ShouldClose()) break;
      window->FramebufferSize(&width, &height);
    }
    if (!options.replay_path.empty() && !still && options.benchmark_seconds == 0.0)
      replay.Advance(Seconds(Clock::now() - start), &live);
    const double elapsed = Seconds(Clock::now() - start);
    pending_change |= live.CopyIfNewer(&scene);  // kept until drawn: an early wake must not lose it
    const bool time_up = (options.seconds > 0.0 && elapsed >= options.seconds) ||
                         (options.benchmark_seconds > 0.0 && elapsed >= options.benchmark_seconds) ||
                         (options.frames > 0 && live.FramesReceived() >= options.frames) ||
                         (still && !options.replay_path.empty()) || interrupted;
    if (paced && !time_up) {
      if (redraw.WaitBefore(elapsed) > 0.0) continue;  // woken early by input: drawn when due
      if (board) {
        const std::uint64_t updates = board->View().updates;
        pending_change |= updates != board_updates;
        board_updates = updates;
      }
      if (!redraw.ShouldDraw(elapsed, pending_change, std::exchange(input_seen, false))) {
        glfwWaitEventsTimeout(redraw.period_s());  // nothing new: look again a frame later, or at input
        continue;
      }
    }
    if (headless && still && !time_up) {  // nothing to show until the end: just wait for frames
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      live.CopyIfNewer(&scene);
      const auto now = Clock::now();
      rate.Update(scene, Seconds(now - start), Seconds(now - last));
      last = now;
      continue;
    }
    draw_frame(width, height, false);
    redraw.Drawn(elapsed);
    pending_change = false;
    if (time_up) {
      glFinish();
      if (!options.png_path.empty()) {
        const Image image = ReadFramebuffer(width, height);
        if (!WritePng(options.png_path, image, &error)) {
          std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
          ok = false;
        }
      }
      if (!options.plot_png_path.empty()) {
        draw_frame(width, height, true);
        glFinish();
        if (!WritePng(options.plot_png_path, ReadFramebuffer(width, height), &error)) {
          std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
          ok = false;
        }
      }
      break;
    }
    if (window) window->Swap();
  }
  if (options.benchmark_seconds > 0.0) {
    glFinish();
    const double total_s = Seconds(Clock::now() - first_drawn);
    drawn -= 1;  // frames after the first
    const std::size_t triangles = scene.triangles ? scene.triangles->parts.size() : 0;
    std::printf("benchmark: %llu frames in %.2f s = %.1f fps (GL work %.2f ms/frame), %zu vertex slots, %zu triangles, "
                "%dx%d, %s, renderer %s\n",
                static_cast<unsigned long long>(drawn), total_s, drawn / total_s, 1e3 * render_s / std::max<double>(drawn, 1),
                scene.positions_m.size() / 3, triangles, width, height, window ? "window" : "off-screen",
                reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  }
  std::printf("viewer: session %s, frames %llu, drawn %llu (with a mesh %llu), last seq %llu, sim time %.3f s, %s\n",
              watched.c_str(), static_cast<unsigned long long>(live.FramesReceived()),
              static_cast<unsigned long long>(drawn), static_cast<unsigned long long>(drawn_with_mesh),
              static_cast<unsigned long long>(live.LastSeq()), scene.sim_time_s, scene.connection.c_str());
  if (stream) std::printf("viewer: reconnects %llu\n", static_cast<unsigned long long>(stream->reconnects()));
  if (board) {
    const ClassView class_view = board->View();
    std::printf("viewer: class %s, updates %llu, sessions %zu, not running %zu, %s\n", class_view.class_name.c_str(),
                static_cast<unsigned long long>(class_view.updates), class_view.sessions.size(),
                class_view.missing.size(), class_view.connection.c_str());
  }
  std::fflush(stdout);
  if (!WriteFinalMesh(options, stream ? stream->StopAndTakeMesh() : replay.Mesh(), watched)) ok = false;
  stream.reset();
  board.reset();
  renderer.reset();
  ImGui_ImplOpenGL3_Shutdown();
  if (window) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  return ok ? 0 : 1;
}

}  // namespace hapsim::gui
