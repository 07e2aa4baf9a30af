// hapsim-ctl: the session-control RPCs from a shell — what an instructor's
// panel does: list/create/close sessions, pause/resume/reset, export a mesh
// snapshot, submit and read scores, check server health.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <unistd.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "hapsim/common/flags.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/mesh_export.h"
#include "hapsim/viewer/session_client.h"

namespace {

// The help's summary: what the tool does and its commands (the flags follow, listed by Flags).
constexpr const char* kUsage =
    "Session control for a hapsim-server (default server 127.0.0.1:50051; every call gives up\n"
    "after --timeout-s seconds, default 10). A server with a class config wants a token: --token,\n"
    "--token-file or the HAPSIM_TOKEN environment variable (docs/classroom.md).\n\ncommands:\n"
    "  scenes                              the scenes a session can run, with every parameter\n"
    "  list                                list sessions with their counters\n"
    "  create [ID | --id ID] [--scene NAME] [--owner NAME] [--param KEY=VALUE]...\n"
    "                                      create a session (prints its id)\n"
    "  info ID | close ID | pause ID | resume ID | reset ID\n"
    "  snapshot ID --obj FILE | --export FILE\n"
    "                                      write the session's current mesh (full precision): OBJ, or by\n"
    "                                      extension .obj, .gltf/.glb (glTF 2.0), .vtk (legacy VTK)\n"
    "  score ID --indicators a,b,c,d,e,f,g [--expert NAME]\n"
    "                                      submit 7 indicator scores (0..10) for a session\n"
    "  scores [ID]                         comprehensive scores of one session or the whole class\n"
    "  join ID                             the DDS partition and domain a device of session ID streams on\n"
    "  watch [CLASS] [--rate-hz R] [--count N]\n"
    "                                      live table of every session of CLASS (like top; no CLASS: every\n"
    "                                      session of a server without a class config); --count: stop after N\n"
    "  push CLASS [--scene NAME] [--param KEY=VALUE]...\n"
    "                                      restart every session of CLASS with this scene (same ids, trainees)\n"
    "  trials [CLASS] [--csv FILE]          every trial's automatic metrics (depth error, layers, peak forces,\n"
    "                                      incision, line deviation, score) as CSV, to stdout or FILE\n"
    "  health                              gRPC health check (exit 0 when SERVING)\n"
    "`hapsim-ctl COMMAND --help` lists a command's own flags.";

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
  // Each session is scored by its own scheme and raters (docs/classroom.md#assessment).
  for (const auto& s : r.sessions()) {
    std::printf("%s experts=%u score=%.4f scheme=%s weights", s.session_id().c_str(), s.experts(),
                s.comprehensive_score(), s.scheme().c_str());
    for (const double w : s.combined_weights()) std::printf(" %.4f", w);
    std::printf("\n");
  }
  std::printf("class mean score %.4f (%d sessions scored)\n", r.class_mean_score(), r.sessions_size());
}

// Every "--param KEY=NUMBER" into *params; false (with the message printed)
// on a malformed one.
bool AddParams(const std::vector<std::string>& texts, google::protobuf::Map<std::string, double>* params) {
  for (const auto& text : texts) {
    if (!hapsim::viewer::AddSceneParam(text, params)) {
      std::fprintf(stderr, "hapsim-ctl: --param wants KEY=NUMBER, got '%s'\n", text.c_str());
      return false;
    }
  }
  return true;
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

// `watch`: the class view as a table, redrawn in place on a terminal (like
// top) or printed block after block into a pipe or file.
int Watch(hapsim::v1::SessionService::Stub& stub, const std::string& token, const std::string& class_name,
          const std::string& rate_text, const std::string& count_text) {
  hapsim::v1::WatchClassRequest req;
  req.set_class_name(class_name);
  long count = 0;
  if (!rate_text.empty()) {
    char* end = nullptr;
    req.set_rate_hz(std::strtod(rate_text.c_str(), &end));
    if (*end != '\0' || !(req.rate_hz() >= 0.1 && req.rate_hz() <= 50.0)) {
      std::fprintf(stderr, "hapsim-ctl: --rate-hz wants [0.1, 50], got '%s'\n", rate_text.c_str());
      return 2;
    }
  }
  if (!count_text.empty()) {
    char* end = nullptr;
    count = std::strtol(count_text.c_str(), &end, 10);
    if (*end != '\0' || count < 1) {
      std::fprintf(stderr, "hapsim-ctl: --count wants a whole number >= 1, got '%s'\n", count_text.c_str());
      return 2;
    }
  }
  grpc::ClientContext ctx;
  hapsim::viewer::AddToken(&ctx, token);
  auto reader = stub.WatchClass(&ctx, req);
  const bool terminal = ::isatty(STDOUT_FILENO) != 0;
  std::map<std::string, std::deque<std::string>> recent;  // session -> last events, newest last
  std::map<std::string, std::uint64_t> event_counts;
  hapsim::v1::ClassStatus status;
  long shown = 0;
  while (reader->Read(&status)) {
    if (terminal) std::printf("\033[H\033[2J");
    std::printf("class %s  update %llu  (%d sessions%s)\n", class_name.empty() ? "(all)" : class_name.c_str(),
                static_cast<unsigned long long>(status.seq()), status.sessions_size(),
                status.missing_sessions_size() ? ", some not running" : "");
    std::printf("%-10s %-10s %-12s %-6s %-9s %8s %-8s %8s %8s %6s %8s %-7s %s\n", "SESSION", "TRAINEE", "SCENE",
                "DEVICE", "CONTACT", "DEPTH_MM", "LAYER", "FORCE_N", "PEAK_N", "LATE", "EVENTS", "SCORE",
                "RECENT EVENTS");
    for (const auto& s : status.sessions()) {
      auto& last = recent[s.session_id()];
      for (const auto& e : s.events()) {
        ++event_counts[s.session_id()];
        last.push_back(e.kind() + "@" + std::to_string(e.t_s()).substr(0, 6) + "s");
        if (last.size() > 3) last.pop_front();
      }
      std::string events;
      for (const auto& e : last) events += (events.empty() ? "" : " ") + e;
      char score[16] = "-";
      if (s.experts() > 0) std::snprintf(score, sizeof score, "%.2f", s.score());
      std::printf("%-10.10s %-10.10s %-12.12s %-6s %-9.9s %8.2f %-8.8s %8.3f %8.3f %6llu %8llu %-7s %s%s\n",
                  s.session_id().c_str(), s.trainee().c_str(), s.scene().c_str(),
                  s.device_streaming() ? "yes" : "no", s.contact_state().c_str(), s.tip_depth_m() * 1e3,
                  s.layer_name().empty() ? "-" : s.layer_name().c_str(), s.force_n(), s.peak_tool_force_n(),
                  static_cast<unsigned long long>(s.late_ticks()),
                  static_cast<unsigned long long>(event_counts[s.session_id()]), score, events.c_str(),
                  s.paused() ? " [paused]" : "");
    }
    for (const auto& m : status.missing_sessions()) std::printf("%-10.10s (not running)\n", m.c_str());
    if (!terminal) std::printf("\n");
    std::fflush(stdout);
    if (count > 0 && ++shown >= count) {
      ctx.TryCancel();
      break;
    }
  }
  const auto s = reader->Finish();
  if (count > 0 && shown >= count) return 0;
  return s.ok() ? 0 : Fail(s);
}

// The commands, with what each takes after its name: a session or class id
// (kOneId, optional when kOptionalId) and its own flags, declared in
// AddCommandFlags.
enum class IdArg { kNone, kOneId, kOptionalId };
const std::map<std::string, IdArg>& Commands() {
  static const std::map<std::string, IdArg> commands = {
      {"scenes", IdArg::kNone},       {"list", IdArg::kNone},        {"create", IdArg::kOptionalId},
      {"health", IdArg::kNone},       {"info", IdArg::kOneId},       {"close", IdArg::kOneId},
      {"pause", IdArg::kOneId},       {"resume", IdArg::kOneId},     {"reset", IdArg::kOneId},
      {"snapshot", IdArg::kOneId},    {"score", IdArg::kOneId},      {"join", IdArg::kOneId},
      {"scores", IdArg::kOptionalId}, {"watch", IdArg::kOptionalId}, {"trials", IdArg::kOptionalId},
      {"push", IdArg::kOneId},
  };
  return commands;
}

// A command's own flags (all optional strings; each command checks what it needs).
struct CommandFlags {
  std::string id, scene, owner, obj, export_file, indicators, expert, rate_hz, count, csv;
  std::vector<std::string> params;
};

void AddCommandFlags(const std::string& command, hapsim::common::Flags* f, CommandFlags* c) {
  if (command == "create") {
    f->Add("id", &c->id, "session id (empty: the server picks one)");
    f->Add("scene", &c->scene, "scene to run (empty: tissue_block)");
    f->Add("owner", &c->owner, "owner's name, shown in lists");
  }
  if (command == "push") f->Add("scene", &c->scene, "scene to restart every session with (empty: tissue_block)");
  if (command == "create" || command == "push") f->AddList("param", &c->params, "scene parameter KEY=NUMBER");
  if (command == "snapshot") {
    f->Add("obj", &c->obj, "write the mesh as OBJ to this file, whatever its extension");
    f->Add("export", &c->export_file, "write the mesh to this file, format by extension: .obj .gltf .glb .vtk");
  }
  if (command == "score") {
    f->Add("indicators", &c->indicators, "7 indicator scores 0..10, comma-separated");
    f->Add("expert", &c->expert, "the rater's name");
  }
  if (command == "watch") {
    f->Add("rate-hz", &c->rate_hz, "updates per second, [0.1, 50] (empty: the server's default)");
    f->Add("count", &c->count, "stop after this many updates (empty: until Ctrl-C)");
  }
  if (command == "trials") f->Add("csv", &c->csv, "write the CSV to this file (empty: stdout)");
}

}  // namespace

int main(int argc, char** argv) {
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  double timeout_s = 10.0;
  hapsim::common::Flags flags("hapsim-ctl", kUsage, "[flags] COMMAND [ID] [command flags]");
  flags.Add("server", &connection.address, "server address HOST:PORT");
  flags.Add("timeout-s", &timeout_s, "every call gives up after this long [s], (0, 3600]");
  hapsim::viewer::AddConnectionFlags(&flags, &connection, &connection_flags);
  std::string error;
  int command_at = argc;
  switch (flags.Parse(argc, argv, &error, &command_at)) {
    case hapsim::common::Flags::Result::kHelp:
      std::fputs(flags.Help().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kError:
      std::fprintf(stderr, "hapsim-ctl: %s\n", error.c_str());
      return 2;
    case hapsim::common::Flags::Result::kOk:
      break;
  }
  if (const std::string bad =
          hapsim::common::FirstFlagOutOfRange({{timeout_s > 0.0 && timeout_s <= 3600.0, "--timeout-s", "(0, 3600]"}});
      !bad.empty()) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", bad.c_str());
    return 2;
  }
  if (command_at >= argc) {
    std::fputs(flags.Help().c_str(), stderr);
    return 2;
  }
  const std::string command = argv[command_at];
  const auto known = Commands().find(command);
  if (known == Commands().end()) {
    std::fprintf(stderr, "hapsim-ctl: unknown command '%s' (see hapsim-ctl --help)\n", command.c_str());
    return 2;
  }
  CommandFlags options;
  std::vector<std::string> ids;
  hapsim::common::Flags command_flags("hapsim-ctl " + command,
                                      "One command of hapsim-ctl (hapsim-ctl --help lists them).",
                                      known->second == IdArg::kNone    ? "[flags]"
                                      : known->second == IdArg::kOneId ? "ID [flags]"
                                                                       : "[ID] [flags]");
  AddCommandFlags(command, &command_flags, &options);
  command_flags.AllowPositionals(&ids);
  switch (command_flags.Parse(argc - command_at, argv + command_at, &error)) {
    case hapsim::common::Flags::Result::kHelp:
      std::fputs(command_flags.Help().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kError:
      if (const auto at = error.find("see --help"); at != std::string::npos) {
        error.replace(at, 10, "see hapsim-ctl " + command + " --help");
      }
      std::fprintf(stderr, "hapsim-ctl %s: %s\n", command.c_str(), error.c_str());
      return 2;
    case hapsim::common::Flags::Result::kOk:
      break;
  }
  if (known->second == IdArg::kNone && !ids.empty()) {
    std::fprintf(stderr, "hapsim-ctl %s: takes no id, got '%s'\n", command.c_str(), ids[0].c_str());
    return 2;
  }
  if (ids.size() > 1) {
    std::fprintf(stderr, "hapsim-ctl %s: takes one id, got '%s' and '%s'\n", command.c_str(), ids[0].c_str(),
                 ids[1].c_str());
    return 2;
  }
  if (known->second == IdArg::kOneId && ids.empty()) {
    std::fprintf(stderr, "hapsim-ctl: %s needs a %s\n", command.c_str(),
                 command == "push" ? "class name" : "session id");
    return 2;
  }
  const std::string id = ids.empty() ? "" : ids[0];
  if (!hapsim::viewer::FinishConnectionFlags(connection_flags, &connection, &error)) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", error.c_str());
    return 2;
  }

  std::shared_ptr<grpc::Channel> channel;
  try {
    channel = hapsim::viewer::MakeChannel(connection);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", e.what());
    return 2;
  }
  auto stub = hapsim::v1::SessionService::NewStub(channel);
  if (command == "watch") return Watch(*stub, connection.token, id, options.rate_hz, options.count);
  grpc::ClientContext ctx;
  hapsim::viewer::AddToken(&ctx, connection.token);
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
    if (!id.empty() && !options.id.empty()) {
      std::fprintf(stderr, "hapsim-ctl create: give the id once (ID or --id), got '%s' and '%s'\n", id.c_str(),
                   options.id.c_str());
      return 2;
    }
    req.set_session_id(id.empty() ? options.id : id);
    req.set_scene(options.scene);
    req.set_owner(options.owner);
    if (!AddParams(options.params, req.mutable_params())) return 2;
    hapsim::v1::SessionInfo info;
    const auto s = stub->CreateSession(&ctx, req, &info);
    if (!s.ok()) return Fail(s);
    PrintInfo(info);
    return 0;
  }
  hapsim::v1::SessionRef ref;
  ref.set_session_id(id);
  if (command == "info" || command == "pause" || command == "resume" || command == "reset") {
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
    hapsim::v1::CloseSessionResponse r;
    const auto s = stub->CloseSession(&ctx, ref, &r);
    if (!s.ok()) return Fail(s);
    std::printf("closed %s\n", id.c_str());
    return 0;
  }
  if (command == "snapshot") {
    const bool as_obj = !options.obj.empty();  // --obj FILE: OBJ whatever the extension
    const std::string obj = as_obj ? options.obj : options.export_file;
    if (obj.empty() || (as_obj && !options.export_file.empty())) {
      std::fprintf(stderr, "hapsim-ctl: snapshot ID --obj FILE | --export FILE\n");
      return 2;
    }
    hapsim::v1::MeshSnapshot snap;
    const auto s = stub->GetSnapshot(&ctx, ref, &snap);
    if (!s.ok()) return Fail(s);
    hapsim::viewer::CompactMesh mesh;
    mesh.vertices_m = Eigen::Map<const Eigen::Matrix3Xd>(snap.positions_m().data(), 3, snap.positions_m_size() / 3);
    mesh.triangles.assign(snap.triangles().begin(), snap.triangles().end());
    for (const auto p : snap.triangle_parts()) mesh.triangle_parts.push_back(static_cast<std::uint16_t>(p));
    mesh.part_names.assign(snap.part_names().begin(), snap.part_names().end());
    if (mesh.triangle_parts.size() * 3 != mesh.triangles.size()) mesh.part_names.clear();  // an older server: one group
    std::string write_error;
    const std::string comment = "hapsim snapshot of " + id + " at sim time " + std::to_string(snap.sim_time_s());
    bool written;
    if (as_obj) {
      written = hapsim::viewer::WriteObj(obj, mesh, comment);
      if (!written) write_error = "cannot write " + obj;
    } else {
      written = hapsim::viewer::WriteMeshFile(obj, mesh, comment, &write_error);
    }
    if (!written) {
      std::fprintf(stderr, "hapsim-ctl: %s\n", write_error.c_str());
      return 1;
    }
    std::printf("wrote %s: %d vertices, %d triangles, sim time %.3f s\n", obj.c_str(), snap.positions_m_size() / 3,
                snap.triangles_size() / 3, snap.sim_time_s());
    return 0;
  }
  if (command == "score") {
    hapsim::v1::SubmitScoresRequest req;
    req.set_session_id(id);
    req.set_expert(options.expert);
    if (!ParseIndicators(options.indicators, &req)) {
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
  if (command == "join") {
    hapsim::v1::JoinSessionResponse r;
    const auto s = stub->JoinSession(&ctx, ref, &r);
    if (!s.ok()) return Fail(s);
    std::printf("session=%s scene=%s dds_domain=%u dds_partition=%s\n", r.session_id().c_str(), r.scene().c_str(),
                r.dds_domain(), r.dds_partition().c_str());
    std::printf("start the device with: hapsim-bridge --session %s --dds-domain %u\n", r.session_id().c_str(),
                r.dds_domain());
    return 0;
  }
  if (command == "trials") {
    hapsim::v1::TrialQuery q;
    q.set_class_name(id);
    hapsim::v1::TrialReport r;
    const auto s = stub->GetTrials(&ctx, q, &r);
    if (!s.ok()) return Fail(s);
    const std::string& file = options.csv;
    if (file.empty()) {
      std::fputs(r.csv().c_str(), stdout);
      return 0;
    }
    std::FILE* f = std::fopen(file.c_str(), "w");
    const bool written = f && std::fputs(r.csv().c_str(), f) >= 0;
    if (!f || std::fclose(f) != 0 || !written) {
      std::fprintf(stderr, "hapsim-ctl: cannot write %s\n", file.c_str());
      return 1;
    }
    std::printf("wrote %u trials to %s\n", r.trials(), file.c_str());
    return 0;
  }
  if (command == "push") {
    hapsim::v1::PushScenarioRequest req;
    req.set_class_name(id);
    req.set_scene(options.scene);
    if (!AddParams(options.params, req.mutable_params())) return 2;
    hapsim::v1::PushScenarioResponse r;
    const auto s = stub->PushScenario(&ctx, req, &r);
    if (!s.ok()) return Fail(s);
    for (const auto& i : r.sessions()) PrintInfo(i);
    std::printf("pushed %s to %d sessions\n", req.scene().empty() ? "tissue_block" : req.scene().c_str(),
                r.sessions_size());
    return 0;
  }
  std::fprintf(stderr, "hapsim-ctl: command '%s' has no handler\n", command.c_str());
  return 2;
}
