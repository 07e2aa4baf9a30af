#include "viewer_loop.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <thread>
#include <utility>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "hapsim/gui/gl.h"
#include "hapsim/gui/image.h"

namespace hapsim::gui {

namespace {

std::atomic<bool> interrupted{false};
void OnStopSignal(int) { interrupted = true; }

// Set by the window's input callbacks (GLFW calls them on the render thread,
// inside glfwPollEvents/glfwWaitEventsTimeout): a redraw is due.
bool input_seen = false;

double Seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

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

}  // namespace

void CatchStopSignals() {
  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
}

void WatchWindowInput(GLFWwindow* window) {
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

ViewerLoop::ViewerLoop(const GuiOptions& options, const GlSurface& surface, viewer::FrameLogWriter* recorder,
                       FrameReplay* replay)
    : options_(options),
      surface_(surface),
      recorder_(recorder),
      replay_(replay),
      io_(ImGui::GetIO()),
      replaying_(!options.replay_path.empty()),
      console_(!options.class_name.empty() && !replaying_),
      still_(surface.headless && options.benchmark_seconds == 0.0),
      paced_(surface.window && options.benchmark_seconds == 0.0),
      watched_(options.viewer.session),
      redraw_(options.max_fps),
      width_(options.width_px),
      height_(options.height_px) {
  if (options.camera) camera_.pose = *options.camera;
  fitted_ = options.camera.has_value();
  view_.follow_tool = options.follow_tool;
  view_.render = options.render;
}

bool ViewerLoop::Start(std::string* error) {
  try {
    renderer_ = std::make_unique<SceneRenderer>();
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  if (replaying_)
    live_.SetConnection("replay of " + options_.replay_path);
  else
    Watch(watched_);
  if (console_) {
    board_ = std::make_unique<ClassBoard>(options_.connection, options_.class_name, options_.class_rate_hz);
    past_ = std::make_unique<PastTrials>(options_.connection, options_.class_name);
    past_->Refresh();
    if (!options_.open_trial.empty()) past_->Open(options_.open_trial);
  }
  if (!replaying_) controls_ = std::make_unique<SessionControls>(options_.connection);
  start_ = last_ = Clock::now();
  if (replaying_ && (still_ || options_.benchmark_seconds > 0.0)) replay_->PlayAll(&live_);
  return true;
}

void ViewerLoop::Watch(const std::string& session) {
  stream_.reset();
  live_.Clear();
  watched_ = session;
  if (session.empty()) return;
  viewer::ViewerOptions stream_options = options_.viewer;
  stream_options.session = session;
  stream_ = std::make_unique<StreamWorker>(options_.connection, stream_options, &live_, recorder_);
}

// No --session: the class's first session, once the class lists one (never a
// session outside the class, which would be refused).
void ViewerLoop::PickFirstSession() {
  if (!console_ || !watched_.empty() || picked_first_) return;
  const ClassView class_view = board_->View();
  if (class_view.sessions.empty()) return;
  Watch(class_view.sessions.front().status.session_id());
  picked_first_ = true;
}

void ViewerLoop::FollowPastTrials() {
  if (!past_) return;
  const std::uint64_t opened = past_view_.opened;
  past_view_ = past_->Snapshot();
  if (past_view_.opened != opened && past_view_.replay) {
    Watch(past_view_.replay->session().session_id());
    fitted_ = options_.camera.has_value();
    picked_first_ = true;  // the replay, not the class's first trainee
  }
  const auto now = Clock::now();
  if (past_view_.replay && now - past_polled_ > std::chrono::milliseconds(500)) {
    past_->PollReplay();
    past_polled_ = now;
  }
}

bool ViewerLoop::Run() {
  while (true) {
    FollowPastTrials();
    PickFirstSession();
    if (surface_.window && !PollWindow()) break;
    if (replaying_ && !still_ && options_.benchmark_seconds == 0.0) {
      replay_->Advance(Seconds(Clock::now() - start_), &live_);
    }
    const double elapsed = Seconds(Clock::now() - start_);
    pending_change_ |= live_.CopyIfNewer(&scene_);  // kept until drawn: an early wake must not lose it
    const bool time_up = TimeUp(elapsed);
    if (paced_ && !time_up && !DueForDraw(elapsed)) continue;
    if (surface_.headless && still_ && !time_up) {  // nothing to show until the end: just wait for frames
      WaitForFrames();
      continue;
    }
    DrawFrame(false);
    redraw_.Drawn(elapsed);
    pending_change_ = false;
    if (time_up) {
      WritePictures();
      break;
    }
    if (surface_.window) surface_.window->Swap();
  }
  return ok_;
}

bool ViewerLoop::PollWindow() {
  const double wait = paced_ ? redraw_.WaitBefore(Seconds(Clock::now() - start_)) : 0.0;
  if (wait > 0.0)
    glfwWaitEventsTimeout(wait);  // sleep until the next draw may happen, or input comes
  else
    glfwPollEvents();
  if (surface_.window->ShouldClose()) return false;
  surface_.window->FramebufferSize(&width_, &height_);
  return true;
}

bool ViewerLoop::TimeUp(double elapsed_s) const {
  return (options_.seconds > 0.0 && elapsed_s >= options_.seconds) ||
         (options_.benchmark_seconds > 0.0 && elapsed_s >= options_.benchmark_seconds) ||
         (options_.frames > 0 && live_.FramesReceived() >= options_.frames) || (still_ && replaying_) || interrupted;
}

// A paced window draws when something changed, input came, or the idle
// refresh is due, and never sooner than max_fps allows.
bool ViewerLoop::DueForDraw(double elapsed_s) {
  if (redraw_.WaitBefore(elapsed_s) > 0.0) return false;  // woken early by input: drawn when due
  if (board_) {
    const std::uint64_t updates = board_->View().updates;
    pending_change_ |= updates != board_updates_;
    board_updates_ = updates;
  }
  if (!redraw_.ShouldDraw(elapsed_s, pending_change_, std::exchange(input_seen, false))) {
    glfwWaitEventsTimeout(redraw_.period_s());  // nothing new: look again a frame later, or at input
    return false;
  }
  return true;
}

void ViewerLoop::WaitForFrames() {
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  live_.CopyIfNewer(&scene_);
  const auto now = Clock::now();
  rate_.Update(scene_, Seconds(now - start_), Seconds(now - last_));
  last_ = now;
}

void ViewerLoop::DrawFrame(bool plots_only) {
  const auto now = Clock::now();
  const double dt = std::max(Seconds(now - last_), 1e-4);
  last_ = now;
  live_.CopyIfNewer(&scene_);
  rate_.Update(scene_, Seconds(now - start_), dt);
  if (options_.benchmark_seconds > 0.0) ++scene_.version;  // as if a delta moved every vertex each frame
  BeginImGuiFrame(dt);
  const int panel_w = options_.panels && !plots_only ? (console_ ? 540 : 380) : 0;
  if (plots_only)
    DrawPlotsOnly();
  else if (panel_w > 0)
    DrawPanels(panel_w);
  if (surface_.window) HandleMouse(io_, &camera_, &view_, height_);
  UpdateCamera();
  ImGui::Render();
  Render(plots_only, panel_w);
  if (drawn_++ == 0) first_drawn_ = Clock::now();
  if (scene_.triangles) ++drawn_with_mesh_;
}

void ViewerLoop::BeginImGuiFrame(double dt_s) {
  io_.DisplaySize = ImVec2(static_cast<float>(width_), static_cast<float>(height_));
  io_.DeltaTime = static_cast<float>(dt_s);
  ImGui_ImplOpenGL3_NewFrame();
  if (surface_.window) ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void ViewerLoop::DrawPlotsOnly() {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(io_.DisplaySize);
  ImGui::Begin("plots", nullptr, ImGuiWindowFlags_NoDecoration);
  ImGui::Text("session %s, sim time %.2f s, %zu samples", watched_.c_str(), scene_.sim_time_s, scene_.history.size());
  DrawForcePlots(scene_, 0.0f, (io_.DisplaySize.y - 40.0f) / 2.0f);
  ImGui::End();
}

void ViewerLoop::DrawPanels(int panel_w) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(panel_w), io_.DisplaySize.y));
  ImGui::Begin("hapsim", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  if (console_ && ImGui::CollapsingHeader("Class", ImGuiTreeNodeFlags_DefaultOpen)) {
    const std::string clicked = DrawClassConsole(board_->View(), watched_, controls_.get());
    if (!clicked.empty() && clicked != watched_) {
      Watch(clicked);
      fitted_ = options_.camera.has_value();
    }
  }
  if (console_ && ImGui::CollapsingHeader("Past trials", ImGuiTreeNodeFlags_DefaultOpen)) {
    const std::string clicked = DrawPastTrials(past_view_, watched_, past_.get(), &past_panel_);
    if (!clicked.empty() && clicked != watched_) {
      Watch(clicked);
      fitted_ = options_.camera.has_value();
    }
  }
  if (!watched_.empty() || replaying_) {
    if (ImGui::CollapsingHeader("Session", ImGuiTreeNodeFlags_DefaultOpen))
      DrawSessionPanel(scene_, replaying_ ? "(recording)" : watched_,
                       replaying_ ? options_.replay_path : options_.connection.address, rate_, &view_, controls_.get());
    if (ImGui::CollapsingHeader("Force", ImGuiTreeNodeFlags_DefaultOpen)) DrawForcePlots(scene_, 0.0f, 150.0f);
    if (ImGui::CollapsingHeader("Events", ImGuiTreeNodeFlags_DefaultOpen)) DrawEventList(scene_);
  }
  ImGui::End();
}

void ViewerLoop::UpdateCamera() {
  if (scene_.triangles && (!fitted_ || view_.reset_view)) {
    camera_.Fit(scene_.lo_m, scene_.hi_m);
    fitted_ = true;
  }
  view_.reset_view = false;
  if (view_.follow_tool && scene_.tool.valid) camera_.pose.target_m = scene_.tool.tip_m;
}

void ViewerLoop::Render(bool plots_only, int panel_w) {
  glBindFramebuffer(GL_FRAMEBUFFER, surface_.headless ? surface_.headless->framebuffer() : 0);
  const auto render_start = Clock::now();
  if (plots_only) {  // the plots alone, on an opaque background
    glViewport(0, 0, width_, height_);
    glClearColor(0.06f, 0.06f, 0.06f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  } else {
    renderer_->SetTriangleBudget(view_.render.max_triangles);
    renderer_->Upload(scene_);
    view_.mesh_triangles = renderer_->mesh_triangles();
    view_.drawn_triangles = renderer_->drawn_triangles();
    renderer_->Draw(scene_, camera_, panel_w, 0, std::max(width_ - panel_w, 1), height_, view_.render);
  }
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  render_s_ += Seconds(Clock::now() - render_start);
}

void ViewerLoop::WritePictures() {
  glFinish();
  std::string error;
  if (!options_.png_path.empty() && !WritePng(options_.png_path, ReadFramebuffer(width_, height_), &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    ok_ = false;
  }
  if (!options_.plot_png_path.empty()) {
    DrawFrame(true);
    glFinish();
    if (!WritePng(options_.plot_png_path, ReadFramebuffer(width_, height_), &error)) {
      std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
      ok_ = false;
    }
  }
}

void ViewerLoop::PrintBenchmark() {
  glFinish();
  const double total_s = Seconds(Clock::now() - first_drawn_);
  drawn_ -= 1;  // frames after the first
  const std::size_t triangles = scene_.triangles ? scene_.triangles->parts.size() : 0;
  std::printf(
      "benchmark: %llu frames in %.2f s = %.1f fps (GL work %.2f ms/frame), %zu vertex slots, %zu triangles, "
      "%dx%d, %s, renderer %s\n",
      static_cast<unsigned long long>(drawn_), total_s, static_cast<double>(drawn_) / total_s,
      1e3 * render_s_ / std::max<double>(static_cast<double>(drawn_), 1), scene_.positions_m.size() / 3, triangles,
      width_, height_, surface_.window ? "window" : "off-screen",
      reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
}

void ViewerLoop::PrintSummary() {
  if (options_.benchmark_seconds > 0.0) PrintBenchmark();
  std::printf("viewer: session %s, frames %llu, drawn %llu (with a mesh %llu), last seq %llu, sim time %.3f s, %s\n",
              watched_.c_str(), static_cast<unsigned long long>(live_.FramesReceived()),
              static_cast<unsigned long long>(drawn_), static_cast<unsigned long long>(drawn_with_mesh_),
              static_cast<unsigned long long>(live_.LastSeq()), scene_.sim_time_s, scene_.connection.c_str());
  if (stream_) std::printf("viewer: reconnects %llu\n", static_cast<unsigned long long>(stream_->reconnects()));
  if (board_) {
    const ClassView class_view = board_->View();
    std::printf("viewer: class %s, updates %llu, sessions %zu, not running %zu, %s\n", class_view.class_name.c_str(),
                static_cast<unsigned long long>(class_view.updates), class_view.sessions.size(),
                class_view.missing.size(), class_view.connection.c_str());
  }
  if (past_) {
    const PastTrials::View past = past_->Snapshot();
    std::printf("viewer: past trials %zu listed, replays opened %llu", past.trials.size(),
                static_cast<unsigned long long>(past.opened));
    if (past.replay) {
      const auto& r = *past.replay;
      std::printf(", %s of %s at %.3f/%.3f s, checkpoints %llu matched %llu diverged", r.session().session_id().c_str(),
                  r.recording_id().c_str(), r.trial_s(), r.trial_length_s(),
                  static_cast<unsigned long long>(r.checkpoints_matched()),
                  static_cast<unsigned long long>(r.checkpoints_diverged()));
    }
    std::printf("%s%s\n", past.last_result.empty() ? "" : "; last: ", past.last_result.c_str());
  }
  std::fflush(stdout);
}

std::optional<viewer::CompactMesh> ViewerLoop::TakeFinalMesh() {
  return stream_ ? stream_->StopAndTakeMesh() : replay_->Mesh();
}

void ViewerLoop::Release() {
  stream_.reset();
  board_.reset();
  past_.reset();  // closes the replay it opened
  renderer_.reset();
}

}  // namespace hapsim::gui
