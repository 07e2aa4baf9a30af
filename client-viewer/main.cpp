// hapsim-viewer: subscribes to a session's mesh stream. In a window (the
// default when built with the GUI) it draws the mesh, tool, force and events
// with live panels, or the instructor's class console with --class. With
// --headless it keeps the mesh current from keyframe + deltas and, at the
// end (--frames, --seconds or SIGINT/SIGTERM), writes it as OBJ/glTF/VTK and
// prints frame, byte and gap counts; add --png/--plot-png for pictures drawn
// off screen (no display needed).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <thread>

#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "hapsim/common/flags.h"
#include "hapsim/common/logging.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_export.h"
#include "hapsim/viewer/viewer_client.h"
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

}  // namespace

int main(int argc, char** argv) {
  std::string obj_path, export_path, log_level = "info";
  std::string png_path, plot_png_path, size_text = "1280x720", class_name, replay_path, record_path, camera_text;
  double benchmark_seconds = 0.0, class_rate_hz = 10.0, max_fps = 60.0;
  bool panels = true, follow_tool = false, vsync = true;
  bool show_tool = true, show_force = true, show_events = true, see_through = true;
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  hapsim::viewer::ViewerOptions options;
  int frames = 0, drop_seq = -1, ack_window = 2;
  int max_triangles = static_cast<int>(kDefaultMaxTriangles);
  bool headless = !kWithGui;
  hapsim::common::Flags flags(
      "hapsim-viewer",
      "Viewer of hapsim: subscribes to a session's frames (keyframe, then deltas) over gRPC and resyncs on a gap.\n"
      "In a window: the mesh lit per part (skin and fat see-through), the tool, the force on it as an arrow,\n"
      "punctures and cuts as markers; panels with the session's state, force vs time and vs depth, events and\n"
      "pause/resume/reset; --class CLASS adds the instructor's console of every session of the class.\n"
      "Mouse: left drag orbits, right drag pans, wheel zooms; R resets the view, F follows the tool.\n"
      "--headless: no window; writes the final mesh (--obj/--export) and counts, and with --png/--plot-png\n"
      "draws pictures off screen (EGL, no display needed).");
  flags.Add("server", &connection.address, "server gRPC address host:port");
  hapsim::viewer::AddConnectionFlags(&flags, &connection, &connection_flags);
  options.session.clear();  // "demo" unless --class: see below
  flags.Add("session", &options.session, "session id to watch (\"\": demo, or with --class the class's first session)");
  flags.Add("name", &options.name, "viewer name shown in server logs");
  flags.Add("headless", &headless,
            kWithGui ? "no window: counts and mesh files; pictures with --png/--plot-png drawn off screen"
                     : "no window (the only mode in this build: built without HAPSIM_WITH_VIEWER_GUI)");
  flags.Add("class", &class_name, "the instructor's class console: every session of this class (window mode)");
  flags.Add("class-rate-hz", &class_rate_hz, "class console update rate [Hz]");
  flags.Add("png", &png_path, "at the end, write the last picture here as PNG (from the window; off screen with --headless or without a display)");
  flags.Add("plot-png", &plot_png_path, "at the end, write the force vs time and force vs depth plots here as PNG");
  flags.Add("size", &size_text, "window or picture size WIDTHxHEIGHT [px]");
  flags.Add("panels", &panels, "draw the panels next to the 3D view (--panels=false: the 3D view only)");
  flags.Add("camera", &camera_text, "fixed camera TX,TY,TZ,DISTANCE,YAW,PITCH[,FOV] (m, deg; default: fit the mesh)");
  flags.Add("follow-tool", &follow_tool, "keep the camera on the tool tip");
  flags.Add("show-tool", &show_tool, "draw the tool from the frame's pose (--show-tool=false hides it)");
  flags.Add("show-force", &show_force, "draw the force on the tool as an arrow (10 mm per N)");
  flags.Add("show-events", &show_events, "mark punctures and cuts where they happened");
  flags.Add("see-through", &see_through, "draw the skin and fat layers translucent");
  flags.Add("max-triangles", &max_triangles,
            "draw a mesh of more triangles simplified to this many (software rendering pays per triangle; 0: all)");
  flags.Add("vsync", &vsync, "sync the window to the display");
  flags.Add("max-fps", &max_fps,
            "the window draws only when something changed, at most this often [Hz] (not --benchmark-seconds)");
  flags.Add("replay", &replay_path, "draw a recording (--record) instead of a server's stream");
  flags.Add("record", &record_path, "record the frame stream here (replay with --replay)");
  flags.Add("benchmark-seconds", &benchmark_seconds,
            "draw flat out for this long, re-uploading every vertex each frame, and print the frame rate");
  flags.Add("frames", &frames, "stop after this many frames (0: no limit)");
  flags.Add("seconds", &options.max_seconds, "stop after this long [s] (0: no limit)");
  flags.Add("max-rate-hz", &options.max_rate_hz, "ask the server for at most this frame rate (0: server's rate)");
  flags.Add("ack-window", &ack_window, "frames the server may send ahead of this viewer's acks (0: no limit)");
  flags.Add("connect-timeout-s", &options.connect_timeout_s, "give up if the server is not reachable by then [s]");
  flags.Add("obj", &obj_path, "write the final mesh here as Wavefront OBJ (metres)");
  flags.Add("export", &export_path,
            "write the final mesh here too, format by extension: .obj, .gltf/.glb (glTF 2.0), .vtk (legacy VTK)");
  flags.Add("debug-drop-seq", &drop_seq, "test only: treat the frame with this seq as lost (forces a resync)");
  flags.Add("log-level", &log_level, "trace, debug, info, warn, error or off");
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case hapsim::common::Flags::Result::kHelp: std::fputs(flags.Help().c_str(), stdout); return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kError: std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str()); return 2;
    case hapsim::common::Flags::Result::kOk: break;
  }
  if (!hapsim::viewer::FinishConnectionFlags(connection_flags, &connection, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 2;
  }
  if (!hapsim::common::SetUpLogging("viewer", log_level)) {
    std::fprintf(stderr, "hapsim-viewer: unknown --log-level '%s'\n", log_level.c_str());
    return 2;
  }
  const bool pictures = !png_path.empty() || !plot_png_path.empty() || benchmark_seconds > 0.0;
  const bool gui = !headless || pictures || !replay_path.empty();
  if (gui && !kWithGui) {
    std::fprintf(stderr, "hapsim-viewer: this build has no renderer (configure with HAPSIM_WITH_VIEWER_GUI=ON); "
                         "--png, --plot-png, --replay and --benchmark-seconds need it; run with --headless\n");
    return 2;
  }
  int width = 0, height = 0;
  if (!ParseSize(size_text, &width, &height)) {
    std::fprintf(stderr, "hapsim-viewer: --size wants WIDTHxHEIGHT within [64, 8192] each, got '%s'\n",
                 size_text.c_str());
    return 2;
  }
  double camera[7];
  if (!camera_text.empty() && !ParseCamera(camera_text, camera)) {
    std::fprintf(stderr,
                 "hapsim-viewer: --camera wants TX,TY,TZ,DISTANCE,YAW,PITCH[,FOV] (distance in (0, 100] m, "
                 "fov in [5, 150] deg), got '%s'\n",
                 camera_text.c_str());
    return 2;
  }
  if (!class_name.empty() && !gui) {
    std::fprintf(stderr,
                 "hapsim-viewer: --class is the window's instructor console: drop --headless, or add --png "
                 "to draw it off screen\n");
    return 2;
  }
  // The instructor's console without --session opens the class's first
  // session once the class lists one; anything else defaults to "demo".
  if (options.session.empty() && class_name.empty()) options.session = "demo";
  using hapsim::common::kMaxFlagSeconds;
  const std::string out_of_range = hapsim::common::FirstFlagOutOfRange({
      {frames >= 0, "--frames", ">= 0"},
      {max_triangles >= 0, "--max-triangles", ">= 0"},
      {options.max_seconds >= 0.0 && options.max_seconds <= kMaxFlagSeconds, "--seconds",
       hapsim::common::kMaxFlagSecondsRange},
      {options.max_rate_hz == 0.0 || (options.max_rate_hz >= 0.01 && options.max_rate_hz <= 1000.0), "--max-rate-hz",
       "0 or [0.01, 1000]"},
      {ack_window >= 0 && ack_window <= 64, "--ack-window", "[0, 64]"},
      {benchmark_seconds >= 0.0 && benchmark_seconds <= 3600.0, "--benchmark-seconds", "[0, 3600]"},
      {class_rate_hz >= 0.1 && class_rate_hz <= 50.0, "--class-rate-hz", "[0.1, 50]"},
      {max_fps >= 1.0 && max_fps <= 1000.0, "--max-fps", "[1, 1000]"},
      {options.connect_timeout_s > 0.0 && options.connect_timeout_s <= 3600.0, "--connect-timeout-s", "(0, 3600]"},
  });
  if (!out_of_range.empty()) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", out_of_range.c_str());
    return 2;
  }
  options.ack_window = static_cast<std::uint32_t>(ack_window);
  options.max_frames = static_cast<std::uint64_t>(frames);
  options.debug_drop_seq = drop_seq;
  options.token = connection.token;

  std::shared_ptr<grpc::Channel> channel;
  try {
    channel = hapsim::viewer::MakeViewerChannel(connection);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", e.what());
    return 2;
  }
#ifdef HAPSIM_WITH_VIEWER_GUI
  if (gui) {
    hapsim::gui::GuiOptions gui_options;
    gui_options.connection = connection;
    gui_options.viewer = options;
    gui_options.class_name = class_name;
    gui_options.class_rate_hz = class_rate_hz;
    gui_options.replay_path = replay_path;
    gui_options.record_path = record_path;
    gui_options.png_path = png_path;
    gui_options.plot_png_path = plot_png_path;
    gui_options.obj_path = obj_path;
    gui_options.export_path = export_path;
    gui_options.headless = headless;
    gui_options.panels = panels;
    gui_options.vsync = vsync;
    gui_options.max_fps = max_fps;
    gui_options.width_px = width;
    gui_options.height_px = height;
    gui_options.seconds = options.max_seconds;
    gui_options.frames = options.max_frames;
    gui_options.benchmark_seconds = benchmark_seconds;
    gui_options.follow_tool = follow_tool;
    gui_options.render.show_tool = show_tool;
    gui_options.render.show_force = show_force;
    gui_options.render.show_events = show_events;
    gui_options.render.see_through_layers = see_through;
    gui_options.render.max_triangles = static_cast<std::size_t>(max_triangles);
    if (!camera_text.empty()) {
      hapsim::gui::CameraPose pose;
      pose.target_m = Eigen::Vector3d(camera[0], camera[1], camera[2]);
      pose.distance_m = camera[3];
      pose.yaw_deg = camera[4];
      pose.pitch_deg = camera[5];
      pose.fov_y_deg = camera[6];
      gui_options.camera = pose;
    }
    return hapsim::gui::RunViewerGui(gui_options);
  }
#endif
  hapsim::viewer::FrameLogWriter recorder;
  if (!record_path.empty()) {
    if (!recorder.Open(record_path, &error)) {
      std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
      return 1;
    }
    options.on_frame = [&recorder](const hapsim::v1::Frame& frame, const hapsim::viewer::MeshCache&) {
      recorder.Write(frame);
    };
  }

  hapsim::viewer::ViewerClient client(channel, options);
  asio::io_context io;
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const std::error_code& ec, int) {
    if (!ec) client.Stop();
  });
  std::thread signal_thread([&io] { io.run(); });
  const bool ok = client.Run();
  io.stop();
  signal_thread.join();

  const auto& s = client.stats();
  const auto& mesh = client.mesh();
  std::printf("viewer: session %s, frames %llu (keyframes %llu, deltas %llu), bytes %llu, gaps %llu, "
              "topology mismatches %llu, malformed %llu, resubscribes %llu\n",
              options.session.c_str(), static_cast<unsigned long long>(s.frames),
              static_cast<unsigned long long>(s.keyframes), static_cast<unsigned long long>(s.deltas),
              static_cast<unsigned long long>(s.bytes), static_cast<unsigned long long>(s.gaps),
              static_cast<unsigned long long>(s.topology_mismatches), static_cast<unsigned long long>(s.malformed),
              static_cast<unsigned long long>(s.resubscribes));
  std::string events;
  for (const auto& [kind, count] : s.events) events += " " + kind + "=" + std::to_string(count);
  std::printf("viewer: last seq %llu, sim time %.3f s, vertices %zu, triangles %zu, peak tool force %.3f N, events:%s\n",
              static_cast<unsigned long long>(mesh.last_seq()), s.last_sim_time_s, mesh.live_vertex_count(),
              mesh.live_triangle_count(), s.peak_tool_force_N, events.empty() ? " none" : events.c_str());
  if (!s.punctures.empty()) {
    std::string list;
    for (const auto& p : s.punctures) list += " " + p;
    std::printf("viewer: punctures (layer@tip depth below z=0):%s\n", list.c_str());
  }
  if (s.topology_frames > 0 || !s.incisions_mm.empty()) {
    std::string list;
    for (const double mm : s.incisions_mm) {
      char item[32];
      std::snprintf(item, sizeof item, " %.2fmm", mm);
      list += item;
    }
    std::printf("viewer: frames with topology edits %llu, incisions:%s\n",
                static_cast<unsigned long long>(s.topology_frames), list.empty() ? " none" : list.c_str());
  }
  std::fflush(stdout);
  const std::string comment = "hapsim session " + options.session + ", seq " + std::to_string(mesh.last_seq()) +
                              ", quantum " + std::to_string(mesh.quantum_m()) + " m";
  if (!obj_path.empty() && mesh.has_mesh() && !hapsim::viewer::WriteObj(obj_path, mesh.Compact(), comment)) {
    std::fprintf(stderr, "hapsim-viewer: cannot write %s\n", obj_path.c_str());
    return 1;
  }
  if (!export_path.empty() && mesh.has_mesh() &&
      !hapsim::viewer::WriteMeshFile(export_path, mesh.Compact(), comment, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return 1;
  }
  if (!ok) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", s.final_status.c_str());
    return 1;
  }
  return 0;
}
