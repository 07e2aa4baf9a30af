// hapsim-viewer: subscribes to a session's mesh stream. In a window (the
// default when built with the GUI) it draws the mesh, tool, force and events
// with live panels, or the instructor's class console with --class. With
// --headless it keeps the mesh current from keyframe + deltas and, at the
// end (--frames, --seconds or SIGINT/SIGTERM), writes it as OBJ/glTF/VTK and
// prints frame, byte and gap counts; add --png/--plot-png for pictures drawn
// off screen (no display needed).
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "hapsim/common/flags.h"
#include "hapsim/common/logging.h"
#include "hapsim/viewer/session_client.h"
#include "hapsim/viewer/session_locator.h"
#include "hapsim/viewer/viewer_client.h"
#include "headless_viewer.h"
#ifdef HAPSIM_WITH_VIEWER_GUI
#include "hapsim/gui/viewer_app.h"
constexpr bool kWithGui = true;
constexpr std::size_t kDefaultMaxTriangles = hapsim::gui::RenderOptions{}.max_triangles;
#else
constexpr bool kWithGui = false;
constexpr std::size_t kDefaultMaxTriangles = 0;
#endif

namespace {

// "WIDTHxHEIGHT" in [64, 8192] each.
bool ParseSize(const std::string& text, int* width, int* height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x') return false;
  if (w < 64 || w > 8192 || h < 64 || h > 8192) return false;
  *width = w;
  *height = h;
  return true;
}

// "TX,TY,TZ,DISTANCE,YAW,PITCH[,FOV]" (m, m, m, m, deg, deg, deg).
bool ParseCamera(const std::string& text, double out[7]) {
  std::stringstream in(text);
  std::string item;
  int n = 0;
  out[6] = 40.0;
  while (std::getline(in, item, ',')) {
    if (n >= 7) return false;
    char* end = nullptr;
    out[n] = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(out[n])) return false;
    ++n;
  }
  return (n == 6 || n == 7) && out[3] > 0.0 && out[3] <= 100.0 && out[6] >= 5.0 && out[6] <= 150.0;
}

constexpr const char* kSummary =
    "Viewer of hapsim: subscribes to a session's frames (keyframe, then deltas) over gRPC and resyncs on a gap.\n"
    "In a window: the mesh lit per part (skin and fat see-through), the tool, the force on it as an arrow,\n"
    "punctures and cuts as markers; panels with the session's state, force vs time and vs depth, events and\n"
    "pause/resume/reset; --class CLASS adds the instructor's console of every session of the class.\n"
    "Mouse: left drag orbits, right drag pans, wheel zooms; R resets the view, F follows the tool.\n"
    "--headless: no window; writes the final mesh (--obj/--export) and counts, and with --png/--plot-png\n"
    "draws pictures off screen (EGL, no display needed).";

// Every flag's value, then what CheckViewerFlags derives from them.
struct ViewerFlags {
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  hapsim::viewer::ViewerOptions options;
  std::string obj_path, export_path, log_level = "info";
  std::string png_path, plot_png_path, size_text = "1280x720", class_name, replay_path, record_path, camera_text;
  std::string open_trial;
  double benchmark_seconds = 0.0, class_rate_hz = 10.0, max_fps = 60.0;
  bool panels = true, follow_tool = false, vsync = true;
  bool show_tool = true, show_force = true, show_events = true, see_through = true;
  int frames = 0, drop_seq = -1, ack_window = 2;
  int max_triangles = static_cast<int>(kDefaultMaxTriangles);
  bool headless = !kWithGui;

  bool gui = false;  // a window, pictures or a replay: the renderer runs
  int width = 0, height = 0;
  double camera[7] = {};
};

// The flags in the order --help lists them: the stream, the window and
// pictures, then limits and files.
void DeclareStreamFlags(hapsim::common::Flags* flags, ViewerFlags* f) {
  flags->Add("server", &f->connection.address, "server gRPC address host:port");
  hapsim::viewer::AddConnectionFlags(flags, &f->connection, &f->connection_flags);
  f->options.session.clear();  // "demo" unless --class: see CheckModeFlags
  flags->Add("session", &f->options.session,
             "session id to watch (\"\": demo, or with --class the class's first session)");
  flags->Add("name", &f->options.name, "viewer name shown in server logs");
  flags->Add("headless", &f->headless,
             kWithGui ? "no window: counts and mesh files; pictures with --png/--plot-png drawn off screen"
                      : "no window (the only mode in this build: built without HAPSIM_WITH_VIEWER_GUI)");
}

void DeclareWindowFlags(hapsim::common::Flags* flags, ViewerFlags* f) {
  flags->Add("class", &f->class_name, "the instructor's class console: every session of this class (window mode)");
  flags->Add("class-rate-hz", &f->class_rate_hz, "class console update rate [Hz]");
  flags->Add("open-trial", &f->open_trial,
             "with --class: open this recorded trial (a recording id, or \"latest\": the class's newest ended trial) "
             "as a replay and watch it, as the console's Past trials Open button does");
  flags->Add("png", &f->png_path,
             "at the end, write the last picture here as PNG (from the window; off screen with --headless or without "
             "a display)");
  flags->Add("plot-png", &f->plot_png_path, "at the end, write the force vs time and force vs depth plots here as PNG");
  flags->Add("size", &f->size_text, "window or picture size WIDTHxHEIGHT [px]");
  flags->Add("panels", &f->panels, "draw the panels next to the 3D view (--panels=false: the 3D view only)");
  flags->Add("camera", &f->camera_text,
             "fixed camera TX,TY,TZ,DISTANCE,YAW,PITCH[,FOV] (m, deg; default: fit the mesh)");
  flags->Add("follow-tool", &f->follow_tool, "keep the camera on the tool tip");
  flags->Add("show-tool", &f->show_tool, "draw the tool from the frame's pose (--show-tool=false hides it)");
  flags->Add("show-force", &f->show_force, "draw the force on the tool as an arrow (10 mm per N)");
  flags->Add("show-events", &f->show_events, "mark punctures and cuts where they happened");
  flags->Add("see-through", &f->see_through, "draw the skin and fat layers translucent");
  flags->Add("max-triangles", &f->max_triangles,
             "draw a mesh of more triangles simplified to this many (software rendering pays per triangle; 0: all)");
  flags->Add("vsync", &f->vsync, "sync the window to the display");
  flags->Add("max-fps", &f->max_fps,
             "the window draws only when something changed, at most this often [Hz] (not --benchmark-seconds)");
  flags->Add("replay", &f->replay_path, "draw a recording (--record) instead of a server's stream");
  flags->Add("record", &f->record_path, "record the frame stream here (replay with --replay)");
  flags->Add("benchmark-seconds", &f->benchmark_seconds,
             "draw flat out for this long, re-uploading every vertex each frame, and print the frame rate");
}

void DeclareLimitAndFileFlags(hapsim::common::Flags* flags, ViewerFlags* f) {
  flags->Add("frames", &f->frames, "stop after this many frames (0: no limit)");
  flags->Add("seconds", &f->options.max_seconds, "stop after this long [s] (0: no limit)");
  flags->Add("max-rate-hz", &f->options.max_rate_hz, "ask the server for at most this frame rate (0: server's rate)");
  flags->Add("ack-window", &f->ack_window, "frames the server may send ahead of this viewer's acks (0: no limit)");
  flags->Add("connect-timeout-s", &f->options.connect_timeout_s, "give up if the server is not reachable by then [s]");
  flags->Add("obj", &f->obj_path, "write the final mesh here as Wavefront OBJ (metres)");
  flags->Add("export", &f->export_path,
             "write the final mesh here too, format by extension: .obj, .gltf/.glb (glTF 2.0), .vtk (legacy VTK)");
  flags->Add("debug-drop-seq", &f->drop_seq, "test only: treat the frame with this seq as lost (forces a resync)");
  flags->Add("log-level", &f->log_level, "trace, debug, info, warn, error or off");
}

// What the flags ask for (window or headless, picture size, camera, class
// console); "" or what is wrong with them.
std::string CheckModeFlags(ViewerFlags* f) {
  const bool pictures = !f->png_path.empty() || !f->plot_png_path.empty() || f->benchmark_seconds > 0.0;
  f->gui = !f->headless || pictures || !f->replay_path.empty();
  if (f->gui && !kWithGui) {
    return "this build has no renderer (configure with HAPSIM_WITH_VIEWER_GUI=ON); "
           "--png, --plot-png, --replay and --benchmark-seconds need it; run with --headless";
  }
  if (!ParseSize(f->size_text, &f->width, &f->height)) {
    return "--size wants WIDTHxHEIGHT within [64, 8192] each, got '" + f->size_text + "'";
  }
  if (!f->camera_text.empty() && !ParseCamera(f->camera_text, f->camera)) {
    return "--camera wants TX,TY,TZ,DISTANCE,YAW,PITCH[,FOV] (distance in (0, 100] m, fov in [5, 150] deg), got '" +
           f->camera_text + "'";
  }
  if (!f->open_trial.empty() && f->class_name.empty()) {
    return "--open-trial opens a past trial in the class console: add --class CLASS";
  }
  if (!f->class_name.empty() && !f->gui) {
    return "--class is the window's instructor console: drop --headless, or add --png to draw it off screen";
  }
  // The instructor's console without --session opens the class's first
  // session once the class lists one; anything else defaults to "demo".
  if (f->options.session.empty() && f->class_name.empty()) f->options.session = "demo";
  return "";
}

std::string CheckFlagRanges(const ViewerFlags& f) {
  using hapsim::common::kMaxFlagSeconds;
  const auto& o = f.options;
  return hapsim::common::FirstFlagOutOfRange({
      {f.frames >= 0, "--frames", ">= 0"},
      {f.max_triangles >= 0, "--max-triangles", ">= 0"},
      {o.max_seconds >= 0.0 && o.max_seconds <= kMaxFlagSeconds, "--seconds", hapsim::common::kMaxFlagSecondsRange},
      {o.max_rate_hz == 0.0 || (o.max_rate_hz >= 0.01 && o.max_rate_hz <= 1000.0), "--max-rate-hz",
       "0 or [0.01, 1000]"},
      {f.ack_window >= 0 && f.ack_window <= 64, "--ack-window", "[0, 64]"},
      {f.benchmark_seconds >= 0.0 && f.benchmark_seconds <= 3600.0, "--benchmark-seconds", "[0, 3600]"},
      {f.class_rate_hz >= 0.1 && f.class_rate_hz <= 50.0, "--class-rate-hz", "[0.1, 50]"},
      {f.max_fps >= 1.0 && f.max_fps <= 1000.0, "--max-fps", "[1, 1000]"},
      {o.connect_timeout_s > 0.0 && o.connect_timeout_s <= 3600.0, "--connect-timeout-s", "(0, 3600]"},
  });
}

// Checks the parsed flags in the order their errors are reported and
// completes the stream options; "" or the message (the caller exits 2).
std::string CheckViewerFlags(ViewerFlags* f) {
  std::string error;
  if (!hapsim::viewer::FinishConnectionFlags(f->connection_flags, &f->connection, &error)) return error;
  if (!hapsim::common::SetUpLogging("viewer", f->log_level)) return "unknown --log-level '" + f->log_level + "'";
  if (error = CheckModeFlags(f); !error.empty()) return error;
  if (error = CheckFlagRanges(*f); !error.empty()) return error;
  f->options.ack_window = static_cast<std::uint32_t>(f->ack_window);
  f->options.max_frames = static_cast<std::uint64_t>(f->frames);
  f->options.debug_drop_seq = f->drop_seq;
  f->options.token = f->connection.token;
  return "";
}

// A watched session on another server of the site than --server names: the
// viewer connects to that one. -1 to go on, else the exit code.
int FollowSession(ViewerFlags* f) {
  if (f->options.session.empty() || !f->class_name.empty() || !f->replay_path.empty()) return -1;
  const auto location = hapsim::viewer::LocateSession(f->connection, f->options.session, f->options.connect_timeout_s,
                                                      /*wait_for_server=*/true);
  if (hapsim::viewer::LocateStopsTheClient(location)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", hapsim::viewer::DescribeStatus(location.status).c_str());
    return 1;
  }
  if (location.moved) {
    spdlog::info("{}: connecting there", hapsim::viewer::DescribeLocation(location));
    f->connection = location.connection;
  }
  return -1;
}

#ifdef HAPSIM_WITH_VIEWER_GUI
hapsim::gui::GuiOptions MakeGuiOptions(const ViewerFlags& f) {
  hapsim::gui::GuiOptions g;
  g.connection = f.connection;
  g.viewer = f.options;
  g.class_name = f.class_name;
  g.class_rate_hz = f.class_rate_hz;
  g.open_trial = f.open_trial;
  g.replay_path = f.replay_path;
  g.record_path = f.record_path;
  g.png_path = f.png_path;
  g.plot_png_path = f.plot_png_path;
  g.obj_path = f.obj_path;
  g.export_path = f.export_path;
  g.headless = f.headless;
  g.panels = f.panels;
  g.vsync = f.vsync;
  g.max_fps = f.max_fps;
  g.width_px = f.width;
  g.height_px = f.height;
  g.seconds = f.options.max_seconds;
  g.frames = f.options.max_frames;
  g.benchmark_seconds = f.benchmark_seconds;
  g.follow_tool = f.follow_tool;
  g.render.show_tool = f.show_tool;
  g.render.show_force = f.show_force;
  g.render.show_events = f.show_events;
  g.render.see_through_layers = f.see_through;
  g.render.max_triangles = static_cast<std::size_t>(f.max_triangles);
  if (!f.camera_text.empty()) {
    hapsim::gui::CameraPose pose;
    pose.target_m = Eigen::Vector3d(f.camera[0], f.camera[1], f.camera[2]);
    pose.distance_m = f.camera[3];
    pose.yaw_deg = f.camera[4];
    pose.pitch_deg = f.camera[5];
    pose.fov_y_deg = f.camera[6];
    g.camera = pose;
  }
  return g;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  ViewerFlags f;
  hapsim::common::Flags flags("hapsim-viewer", kSummary);
  DeclareStreamFlags(&flags, &f);
  DeclareWindowFlags(&flags, &f);
  DeclareLimitAndFileFlags(&flags, &f);
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case hapsim::common::Flags::Result::kHelp:
      std::fputs(flags.Help().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kError:
      std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
      return 2;
    case hapsim::common::Flags::Result::kOk:
      break;
  }
  if (error = CheckViewerFlags(&f); !error.empty()) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 2;
  }
  std::shared_ptr<grpc::Channel> channel;
  try {
    if (const int exit_code = FollowSession(&f); exit_code >= 0) return exit_code;
    channel = hapsim::viewer::MakeViewerChannel(f.connection);  // unreadable TLS files throw
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", e.what());
    return 2;
  }
#ifdef HAPSIM_WITH_VIEWER_GUI
  if (f.gui) return hapsim::gui::RunViewerGui(MakeGuiOptions(f));
#endif
  return hapsim::viewer::RunHeadlessViewer(channel, f.options, {f.record_path, f.obj_path, f.export_path});
}
