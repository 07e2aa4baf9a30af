#include "hapsim/gui/viewer_app.h"

#include <cstdio>
#include <memory>
#include <optional>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <spdlog/spdlog.h>

#include "hapsim/gui/frame_replay.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_export.h"
#include "viewer_loop.h"

namespace hapsim::gui {

namespace {

// A window unless --headless; off screen also when no window opens (no
// display) and the run only writes files (pictures, a mesh).
bool OpenGlSurface(const GuiOptions& options, GlSurface* surface, std::string* error) {
  const bool writes_files = !options.png_path.empty() || !options.plot_png_path.empty() ||
                            options.benchmark_seconds > 0.0 || !options.obj_path.empty() ||
                            !options.export_path.empty();
  bool off_screen = options.headless;
  if (!off_screen) {
    const std::string title =
        "hapsim-viewer — " + (options.class_name.empty() ? options.viewer.session : "class " + options.class_name);
    surface->window = GlWindow::Open(options.width_px, options.height_px, title,
                                     options.vsync && options.benchmark_seconds == 0.0, error);
    if (!surface->window && writes_files) {
      spdlog::info("no window could be opened (no display?): drawing off screen");
      off_screen = true;
    }
  }
  if (off_screen) surface->headless = HeadlessGl::Open(options.width_px, options.height_px, error);
  return surface->window || surface->headless;
}

void StartImGui(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini dropped in the working directory
  ImGui::StyleColorsDark();
  if (window) {
    WatchWindowInput(window);
    ImGui_ImplGlfw_InitForOpenGL(window, true);
  }
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

void StopImGui(bool with_window) {
  ImGui_ImplOpenGL3_Shutdown();
  if (with_window) ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
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

// The surface, the recorder (--record) and the recording (--replay); false
// with *error when one cannot be had.
bool OpenInputsAndOutputs(const GuiOptions& options, GlSurface* surface,
                          std::unique_ptr<viewer::FrameLogWriter>* recorder, FrameReplay* replay, std::string* error) {
  if (!OpenGlSurface(options, surface, error)) return false;
  if (!options.record_path.empty()) {
    *recorder = std::make_unique<viewer::FrameLogWriter>();
    if (!(*recorder)->Open(options.record_path, error)) return false;
  }
  return options.replay_path.empty() || replay->Load(options.replay_path, error);
}

}  // namespace

int RunViewerGui(const GuiOptions& options) {
  std::string error;
  GlSurface surface;
  std::unique_ptr<viewer::FrameLogWriter> recorder;
  FrameReplay replay;
  if (!OpenInputsAndOutputs(options, &surface, &recorder, &replay, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 1;
  }
  CatchStopSignals();
  StartImGui(surface.window ? surface.window->handle() : nullptr);
  ViewerLoop loop(options, surface, recorder.get(), &replay);
  if (!loop.Start(&error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 1;
  }
  bool ok = loop.Run();
  loop.PrintSummary();
  if (!WriteFinalMesh(options, loop.TakeFinalMesh(), loop.watched())) ok = false;
  loop.Release();
  StopImGui(surface.window != nullptr);
  return ok ? 0 : 1;
}

}  // namespace hapsim::gui
