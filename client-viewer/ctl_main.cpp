// hapsim-ctl: the session-control RPCs from a shell — what an instructor's
// panel does: list/create/close sessions, pause/resume/reset, export a mesh
// snapshot, submit and read scores, check server health.
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <cstdlib>
#include <sstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/session_client.h"

namespace {

constexpr const char* kUsage =
    "usage: hapsim-ctl [--server HOST:PORT] [--timeout-s S] COMMAND [ARGS]\n\n"
    "Session control for a hapsim-server (default server 127.0.0.1:50051; every call gives up\n"
    "after --timeout-s seconds, default 10).\n\ncommands:\n"
    "  scenes                              the scenes a session can run, with every parameter\n"
    "  list                                list sessions with their counters\n"
    "  create [--id ID] [--scene NAME] [--owner NAME] [--param KEY=VALUE]...\n"
    "                                      create a session (prints its id)\n"
    "  info ID | close ID | pause ID | resume ID | reset ID\n"
    "  snapshot ID --obj FILE              write the session's current mesh (full precision) as OBJ\n"
    "  score ID --indicators a,b,c,d,e,f,g [--expert NAME]\n"
    "                                      submit 7 indicator scores (0..10) for a session\n"
    "  scores [ID]                         comprehensive scores of one session or the whole class\n"
    "  health                              gRPC health check (exit 0 when SERVING)\n";

int Fail(const grpc::Status& s) {
  std::fprintf(stderr, "hapsim-ctl: %s (%d)\n", s.error_message().c_str(), static_cast<int>(s.error_code()));
  return 1;
}

void PrintInfo(const hapsim::v1::SessionInfo& i) {
  using ull = unsigned long long;
  std::printf("%s scene=%s owner=%s paused=%d sim_time_s=%.3f ticks=%llu late_ticks=%llu device_clocked_ticks=%llu "
              "max_tick_lateness_s=%.6f viewers=%u poses_received=%llu poses_rejected=%llu "
              "poses_from_other_devices=%llu poses_stale=%llu viewer_frames_coalesced=%llu device_streaming=%d owning_device_id=%u force_models_sent=%llu "
              "numerical_resets=%llu peak_tool_force_n=%.4f\n",
              i.session_id().c_str(), i.scene().c_str(), i.owner().c_str(), i.paused() ? 1 : 0, i.sim_time_s(),
              static_cast<ull>(i.ticks()), static_cast<ull>(i.late_ticks()), static_cast<ull>(i.device_clocked_ticks()),
              i.max_tick_lateness_s(), i.viewers(), static_cast<ull>(i.poses_received()),
              static_cast<ull>(i.poses_rejected()), static_cast<ull>(i.poses_from_other_devices()),
              static_cast<ull>(i.poses_stale()), static_cast<ull>(i.viewer_frames_coalesced()),
              i.device_streaming() ? 1 : 0, i.owning_device_id(), static_cast<ull>(i.force_models_sent()),
              static_cast<ull>(i.numerical_resets()), i.peak_tool_force_n());
}

void PrintScores(const hapsim::v1::ScoreReport& r) {
  std::printf("weights (mu=%.2f): combined", r.mu());
  for (const double w : r.combined_weights()) std::printf(" %.4f", w);
  std::printf("\n");
  for (const auto& s : r.sessions()) {
    std::printf("%s experts=%u score=%.4f\n", s.session_id().c_str(), s.experts(), s.comprehensive_score());
  }
  std::printf("class mean score %.4f\n", r.class_mean_score());
}

bool ParseIndicators(const std::string& text, hapsim::v1::SubmitScoresRequest* req) {
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') return false;
    req->add_indicators(v);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string server = "127.0.0.1:50051";
  double timeout_s = 10.0;
  while (args.size() >= 2 && (args[0] == "--server" || args[0] == "--timeout-s")) {
    if (args[0] == "--server") {
      server = args[1];
    } else {
      char* end = nullptr;
      timeout_s = std::strtod(args[1].c_str(), &end);
      if (args[1].empty() || *end != '\0' || !(timeout_s > 0.0 && timeout_s <= 3600.0)) {
        std::fprintf(stderr, "hapsim-ctl: --timeout-s wants seconds in (0, 3600], got '%s'\n", args[1].c_str());
        return 2;
      }
    }
    args.erase(args.begin(), args.begin() + 2);
  }
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  // Named options after the command: --key value
  auto option = [&](const std::string& name) -> std::string {
    for (std::size_t i = 1; i + 1 < args.size(); ++i) {
      if (args[i] == name) return args[i + 1];
    }
    return "";
  };
  auto positional = [&]() -> std::string { return args.size() >= 2 && args[1].rfind("--", 0) != 0 ? args[1] : ""; };
  // Every option after the command must be one the command takes, with a
  // value: a typo is an error, never a silent default.
  const std::map<std::string, std::set<std::string>> options_of = {
      {"create", {"--id", "--scene", "--owner", "--param"}},
      {"snapshot", {"--obj"}},
      {"score", {"--indicators", "--expert"}},
  };
  {
    const auto known = options_of.find(command);
    for (std::size_t i = 1; i < args.size(); ++i) {
      if (args[i].rfind("--", 0) != 0) continue;
      if (known == options_of.end() || !known->second.count(args[i])) {
        std::fprintf(stderr, "hapsim-ctl: %s does not take option '%s'\n%s", command.c_str(), args[i].c_str(), kUsage);
        return 2;
      }
      if (i + 1 >= args.size()) {
        std::fprintf(stderr, "hapsim-ctl: option '%s' needs a value\n", args[i].c_str());
        return 2;
      }
      ++i;
    }
  }

  auto channel = grpc::CreateChannel(server, grpc::InsecureChannelCredentials());
  auto stub = hapsim::v1::SessionService::NewStub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() +
                   std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(timeout_s)));

  if (command == "health") {
    grpc::ByteBuffer response;
    // grpc.health.v1.Health/Check with an empty request: the generic stub
    // avoids needing the health proto here; SERVING is field 1 = 1.
    grpc::GenericStub generic(channel);
    grpc::Slice empty;
    grpc::ByteBuffer request(&empty, 1);
    grpc::Status status;
    bool done = false;
    std::mutex m;
    std::condition_variable cv;
    generic.UnaryCall(&ctx, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                      [&](grpc::Status s) {
                        std::lock_guard lock(m);
                        status = s;
                        done = true;
                        cv.notify_one();
                      });
    std::unique_lock lock(m);
    cv.wait(lock, [&] { return done; });
    if (!status.ok()) return Fail(status);
    std::vector<grpc::Slice> slices;
    (void)response.Dump(&slices);
    std::string bytes;
    for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
    const bool serving = bytes.size() == 2 && bytes[0] == 0x08 && bytes[1] == 0x01;
    std::printf("%s\n", serving ? "SERVING" : "NOT_SERVING");
    return serving ? 0 : 1;
  }
  if (command == "scenes") {
    hapsim::v1::ListScenesResponse r;
    const auto s = stub->ListScenes(&ctx, {}, &r);
    if (!s.ok()) return Fail(s);
    for (const auto& scene : r.scenes()) {
      std::printf("%s: %s\n", scene.name().c_str(), scene.description().c_str());
      for (const auto& p : scene.parameters()) {
        const bool plain = p.unit() == "1" || p.unit() == "count" || p.unit() == "code";  // no unit worth printing
        std::printf("  %-31s default %g%s%s, %s: %s\n", p.name().c_str(), p.default_value(), plain ? "" : " ",
                    plain ? "" : p.unit().c_str(), p.range().c_str(), p.description().c_str());
      }
    }
    return 0;
  }
  if (command == "list") {
    hapsim::v1::ListSessionsResponse r;
    const auto s = stub->ListSessions(&ctx, {}, &r);
    if (!s.ok()) return Fail(s);
    for (const auto& i : r.sessions()) PrintInfo(i);
    return 0;
  }
  if (command == "create") {
    hapsim::v1::CreateSessionRequest req;
    req.set_session_id(option("--id"));
    req.set_scene(option("--scene"));
    req.set_owner(option("--owner"));
    for (std::size_t i = 1; i + 1 < args.size(); ++i) {
      if (args[i] != "--param") continue;
      if (!hapsim::viewer::AddSceneParam(args[i + 1], req.mutable_params())) {
        std::fprintf(stderr, "hapsim-ctl: --param wants KEY=NUMBER, got '%s'\n", args[i + 1].c_str());
        return 2;
      }
    }
    hapsim::v1::SessionInfo info;
    const auto s = stub->CreateSession(&ctx, req, &info);
    if (!s.ok()) return Fail(s);
    PrintInfo(info);
    return 0;
  }
  const std::string id = positional();
  hapsim::v1::SessionRef ref;
  ref.set_session_id(id);
  if (command == "info" || command == "pause" || command == "resume" || command == "reset") {
    if (id.empty()) { std::fprintf(stderr, "hapsim-ctl: %s needs a session id\n", command.c_str()); return 2; }
    hapsim::v1::SessionInfo info;
    grpc::Status s;
    if (command == "info") s = stub->GetSession(&ctx, ref, &info);
    if (command == "pause") s = stub->PauseSession(&ctx, ref, &info);
    if (command == "resume") s = stub->ResumeSession(&ctx, ref, &info);
    if (command == "reset") s = stub->ResetSession(&ctx, ref, &info);
    if (!s.ok()) return Fail(s);
    PrintInfo(info);
    return 0;
  }
  if (command == "close") {
    if (id.empty()) { std::fprintf(stderr, "hapsim-ctl: close needs a session id\n"); return 2; }
    hapsim::v1::CloseSessionResponse r;
    const auto s = stub->CloseSession(&ctx, ref, &r);
    if (!s.ok()) return Fail(s);
    std::printf("closed %s\n", id.c_str());
    return 0;
  }
  if (command == "snapshot") {
    const std::string obj = option("--obj");
    if (id.empty() || obj.empty()) { std::fprintf(stderr, "hapsim-ctl: snapshot ID --obj FILE\n"); return 2; }
    hapsim::v1::MeshSnapshot snap;
    const auto s = stub->GetSnapshot(&ctx, ref, &snap);
    if (!s.ok()) return Fail(s);
    hapsim::viewer::CompactMesh mesh;
    mesh.vertices_m = Eigen::Map<const Eigen::Matrix3Xd>(snap.positions_m().data(), 3, snap.positions_m_size() / 3);
    mesh.triangles.assign(snap.triangles().begin(), snap.triangles().end());
    for (const auto p : snap.triangle_parts()) mesh.triangle_parts.push_back(static_cast<std::uint16_t>(p));
    mesh.part_names.assign(snap.part_names().begin(), snap.part_names().end());
    if (mesh.triangle_parts.size() * 3 != mesh.triangles.size()) mesh.part_names.clear();  // an older server: one group
    if (!hapsim::viewer::WriteObj(obj, mesh, "hapsim snapshot of " + id + " at sim time " + std::to_string(snap.sim_time_s()))) {
      std::fprintf(stderr, "hapsim-ctl: cannot write %s\n", obj.c_str());
      return 1;
    }
    std::printf("wrote %s: %d vertices, %d triangles, sim time %.3f s\n", obj.c_str(), snap.positions_m_size() / 3,
                snap.triangles_size() / 3, snap.sim_time_s());
    return 0;
  }
  if (command == "score") {
    hapsim::v1::SubmitScoresRequest req;
    req.set_session_id(id);
    req.set_expert(option("--expert"));
    if (id.empty() || !ParseIndicators(option("--indicators"), &req)) {
      std::fprintf(stderr, "hapsim-ctl: score ID --indicators a,b,c,d,e,f,g [--expert NAME]\n");
      return 2;
    }
    hapsim::v1::ScoreReport r;
    const auto s = stub->SubmitScores(&ctx, req, &r);
    if (!s.ok()) return Fail(s);
    PrintScores(r);
    return 0;
  }
  if (command == "scores") {
    hapsim::v1::ScoreQuery q;
    q.set_session_id(id);
    hapsim::v1::ScoreReport r;
    const auto s = stub->GetScores(&ctx, q, &r);
    if (!s.ok()) return Fail(s);
    PrintScores(r);
    return 0;
  }
  std::fprintf(stderr, "hapsim-ctl: unknown command '%s'\n%s", command.c_str(), kUsage);
  return 2;
}
