// hapsim-viewer: subscribes to a session's mesh stream. Headless here: it
// keeps the mesh current from keyframe + deltas and, at the end (--frames,
// --seconds or SIGINT/SIGTERM), writes it as OBJ and prints frame, byte and
// gap counts. On-screen rendering is a later piece.
#include <cstdio>
#include <thread>

#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "hapsim/common/flags.h"
#include "hapsim/common/logging.h"
#include "hapsim/viewer/mesh_export.h"
#include "hapsim/viewer/viewer_client.h"

int main(int argc, char** argv) {
  std::string obj_path, export_path, log_level = "info";
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  hapsim::viewer::ViewerOptions options;
  int frames = 0, drop_seq = -1, ack_window = 2;
  bool headless = true;
  hapsim::common::Flags flags("hapsim-viewer",
                               "Viewer of hapsim: subscribes to a session's frames (keyframe, then deltas) over gRPC,\n"
                               "resyncs on a gap, and in headless mode writes the final mesh as OBJ with counts.");
  flags.Add("server", &connection.address, "server gRPC address host:port");
  hapsim::viewer::AddConnectionFlags(&flags, &connection, &connection_flags);
  flags.Add("session", &options.session, "session id to watch");
  flags.Add("name", &options.name, "viewer name shown in server logs");
  flags.Add("headless", &headless, "no window (the only mode in this build)");
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
  if (!headless) {
    std::fprintf(stderr, "hapsim-viewer: this build has no on-screen renderer yet; run with --headless\n");
    return 2;
  }
  using hapsim::common::kMaxFlagSeconds;
  const std::string out_of_range = hapsim::common::FirstFlagOutOfRange({
      {frames >= 0, "--frames", ">= 0"},
      {options.max_seconds >= 0.0 && options.max_seconds <= kMaxFlagSeconds, "--seconds",
       hapsim::common::kMaxFlagSecondsRange},
      {options.max_rate_hz == 0.0 || (options.max_rate_hz >= 0.01 && options.max_rate_hz <= 1000.0), "--max-rate-hz",
       "0 or [0.01, 1000]"},
      {ack_window >= 0 && ack_window <= 64, "--ack-window", "[0, 64]"},
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
