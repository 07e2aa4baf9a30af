#include "headless_viewer.h"

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <cstdio>
#include <thread>
#include <vector>

#include "hapsim/viewer/event_tally.h"
#include "hapsim/viewer/frame_log.h"
#include "hapsim/viewer/mesh_export.h"

namespace hapsim::viewer {

namespace {

using ull = unsigned long long;

// Runs the client until it returns; SIGINT/SIGTERM stop it (and still print and write the mesh).
bool RunUntilStopped(ViewerClient* client) {
  asio::io_context io;
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([client](const std::error_code& ec, int) {
    if (!ec) client->Stop();
  });
  std::thread signal_thread([&io] { io.run(); });
  const bool ok = client->Run();
  io.stop();
  signal_thread.join();
  return ok;
}

// " contact_begin=2 puncture=3", kinds in name order, or " none".
std::string EventCountsText(const EventTally& tally) {
  std::vector<EventKind> kinds;
  for (std::size_t k = 0; k < kEventKindCount; ++k) {
    if (tally.counts[k] > 0) kinds.push_back(static_cast<EventKind>(k));
  }
  std::sort(kinds.begin(), kinds.end(),
            [](EventKind a, EventKind b) { return std::string_view(ToString(a)) < std::string_view(ToString(b)); });
  std::string text;
  for (const EventKind kind : kinds) {
    text.append(" ").append(ToString(kind)).append("=").append(std::to_string(tally.count(kind)));
  }
  return text.empty() ? " none" : text;
}

void PrintStreamCounts(const std::string& session, const ViewerStats& s) {
  std::printf(
      "viewer: session %s, frames %llu (keyframes %llu, deltas %llu), bytes %llu, gaps %llu, "
      "topology mismatches %llu, malformed %llu, resubscribes %llu\n",
      session.c_str(), static_cast<ull>(s.frames), static_cast<ull>(s.keyframes), static_cast<ull>(s.deltas),
      static_cast<ull>(s.bytes), static_cast<ull>(s.gaps), static_cast<ull>(s.topology_mismatches),
      static_cast<ull>(s.malformed), static_cast<ull>(s.resubscribes));
}

void PrintTissueSummary(const ViewerStats& s, const MeshCache& mesh, const EventTally& tally) {
  std::printf(
      "viewer: last seq %llu, sim time %.3f s (first frame at %.3f s), vertices %zu, triangles %zu, peak tool force "
      "%.3f N, events:%s\n",
      static_cast<ull>(mesh.last_seq()), s.last_sim_time_s, s.first_sim_time_s, mesh.live_vertex_count(),
      mesh.live_triangle_count(), s.peak_tool_force_N, EventCountsText(tally).c_str());
  if (!tally.punctures.empty()) {
    std::string list;
    for (const Puncture& p : tally.punctures) {
      char depth[32];
      std::snprintf(depth, sizeof depth, "@%.2fmm", p.depth_mm);
      list += " " + p.layer + depth;
    }
    std::printf("viewer: punctures (layer@tip depth below z=0):%s\n", list.c_str());
  }
  if (tally.topology_frames > 0 || !tally.incisions_mm.empty()) {
    std::string list;
    for (const double mm : tally.incisions_mm) {
      char item[32];
      std::snprintf(item, sizeof item, " %.2fmm", mm);
      list += item;
    }
    std::printf("viewer: frames with topology edits %llu, incisions:%s\n", static_cast<ull>(tally.topology_frames),
                list.empty() ? " none" : list.c_str());
  }
}

// False (with the message printed) when a file cannot be written; no mesh: nothing to write.
bool WriteFinalMesh(const std::string& session, const MeshCache& mesh, const HeadlessOutputs& outputs) {
  if (!mesh.has_mesh()) return true;
  const std::string comment = "hapsim session " + session + ", seq " + std::to_string(mesh.last_seq()) + ", quantum " +
                              std::to_string(mesh.quantum_m()) + " m";
  if (!outputs.obj_path.empty() && !WriteObj(outputs.obj_path, mesh.Compact(), comment)) {
    std::fprintf(stderr, "hapsim-viewer: cannot write %s\n", outputs.obj_path.c_str());
    return false;
  }
  std::string error;
  if (!outputs.export_path.empty() && !WriteMeshFile(outputs.export_path, mesh.Compact(), comment, &error)) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
    return false;
  }
  return true;
}

}  // namespace

int RunHeadlessViewer(std::shared_ptr<grpc::Channel> channel, ViewerOptions options, const HeadlessOutputs& outputs) {
  FrameLogWriter recorder;
  if (!outputs.record_path.empty()) {
    if (std::string error; !recorder.Open(outputs.record_path, &error)) {
      std::fprintf(stderr, "hapsim-viewer: %s\n", error.c_str());
      return 1;
    }
    options.recorder = &recorder;
  }
  EventTally tally;
  options.on_received = [&tally](const ViewerFrame& frame) { tally.Add(frame); };
  ViewerClient client(std::move(channel), options);
  const bool ok = RunUntilStopped(&client);

  PrintStreamCounts(options.session, client.stats());
  PrintTissueSummary(client.stats(), client.mesh(), tally);
  std::fflush(stdout);
  if (!WriteFinalMesh(options.session, client.mesh(), outputs)) return 1;
  if (!ok) {
    std::fprintf(stderr, "hapsim-viewer: %s\n", client.stats().final_status.c_str());
    return 1;
  }
  return 0;
}

}  // namespace hapsim::viewer
