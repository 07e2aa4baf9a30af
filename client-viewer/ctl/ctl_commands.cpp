#include "ctl_commands.h"

#include <grpcpp/generic/generic_stub.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <sstream>

#include "hapsim/viewer/mesh_cache.h"
#include "hapsim/viewer/mesh_export.h"
#include "hapsim/viewer/session_client.h"

namespace hapsim::ctl {

namespace {

using ull = unsigned long long;

void PrintInfo(const hapsim::v1::SessionInfo& i) {
  std::printf(
      "%s scene=%s owner=%s paused=%d sim_time_s=%.3f ticks=%llu late_ticks=%llu device_clocked_ticks=%llu "
      "max_tick_lateness_s=%.6f viewers=%u poses_received=%llu poses_rejected=%llu "
      "poses_from_other_devices=%llu poses_stale=%llu viewer_frames_coalesced=%llu device_streaming=%d "
      "owning_device_id=%u force_models_sent=%llu force_models_held=%llu poses_unused=%llu "
      "numerical_resets=%llu peak_tool_force_n=%.4f\n",
      i.session_id().c_str(), i.scene().c_str(), i.owner().c_str(), i.paused() ? 1 : 0, i.sim_time_s(),
      static_cast<ull>(i.ticks()), static_cast<ull>(i.late_ticks()), static_cast<ull>(i.device_clocked_ticks()),
      i.max_tick_lateness_s(), i.viewers(), static_cast<ull>(i.poses_received()), static_cast<ull>(i.poses_rejected()),
      static_cast<ull>(i.poses_from_other_devices()), static_cast<ull>(i.poses_stale()),
      static_cast<ull>(i.viewer_frames_coalesced()), i.device_streaming() ? 1 : 0, i.owning_device_id(),
      static_cast<ull>(i.force_models_sent()), static_cast<ull>(i.force_models_held()),
      static_cast<ull>(i.poses_unused()), static_cast<ull>(i.numerical_resets()), i.peak_tool_force_n());
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

hapsim::v1::SessionRef RefOf(const CommandCall& call) {
  hapsim::v1::SessionRef ref;
  ref.set_session_id(call.id);
  return ref;
}

// grpc.health.v1.Health/Check with an empty request, waited for. The generic
// stub avoids needing the health proto here.
grpc::Status CheckHealth(CommandCall& call, grpc::ByteBuffer* response) {
  grpc::GenericStub generic(call.channel);
  grpc::Slice empty;
  grpc::ByteBuffer request(&empty, 1);
  grpc::Status status;
  bool done = false;
  std::mutex m;
  std::condition_variable cv;
  generic.UnaryCall(&call.context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, response,
                    [&](grpc::Status s) {
                      std::lock_guard lock(m);
                      status = s;
                      done = true;
                      cv.notify_one();
                    });
  std::unique_lock lock(m);
  cv.wait(lock, [&] { return done; });
  return status;
}

int RunHealth(CommandCall& call) {
  grpc::ByteBuffer response;
  if (const grpc::Status status = CheckHealth(call, &response); !status.ok()) return ReportFailure(status);
  std::vector<grpc::Slice> slices;
  (void)response.Dump(&slices);
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  const bool serving = bytes.size() == 2 && bytes[0] == 0x08 && bytes[1] == 0x01;  // status (field 1) = SERVING (1)
  std::printf("%s\n", serving ? "SERVING" : "NOT_SERVING");
  return serving ? 0 : 1;
}

int RunScenes(CommandCall& call) {
  hapsim::v1::ListScenesResponse r;
  const auto s = call.stub->ListScenes(&call.context, {}, &r);
  if (!s.ok()) return ReportFailure(s);
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

int RunList(CommandCall& call) {
  hapsim::v1::ListSessionsResponse r;
  const auto s = call.stub->ListSessions(&call.context, {}, &r);
  if (!s.ok()) return ReportFailure(s);
  for (const auto& i : r.sessions()) PrintInfo(i);
  return 0;
}

int RunCreate(CommandCall& call) {
  if (!call.id.empty() && !call.flags.id.empty()) {
    std::fprintf(stderr, "hapsim-ctl create: give the id once (ID or --id), got '%s' and '%s'\n", call.id.c_str(),
                 call.flags.id.c_str());
    return 2;
  }
  hapsim::v1::CreateSessionRequest req;
  req.set_session_id(call.id.empty() ? call.flags.id : call.id);
  req.set_scene(call.flags.scene);
  req.set_owner(call.flags.owner);
  if (!AddParams(call.flags.params, req.mutable_params())) return 2;
  hapsim::v1::SessionInfo info;
  const auto s = call.stub->CreateSession(&call.context, req, &info);
  if (!s.ok()) return ReportFailure(s);
  PrintInfo(info);
  return 0;
}

// info, pause, resume, reset: one session's state after the call.
int RunSessionControl(CommandCall& call) {
  const hapsim::v1::SessionRef ref = RefOf(call);
  hapsim::v1::SessionInfo info;
  grpc::Status s;
  if (call.command == "info") s = call.stub->GetSession(&call.context, ref, &info);
  if (call.command == "pause") s = call.stub->PauseSession(&call.context, ref, &info);
  if (call.command == "resume") s = call.stub->ResumeSession(&call.context, ref, &info);
  if (call.command == "reset") s = call.stub->ResetSession(&call.context, ref, &info);
  if (!s.ok()) return ReportFailure(s);
  PrintInfo(info);
  return 0;
}

int RunClose(CommandCall& call) {
  hapsim::v1::CloseSessionResponse r;
  const auto s = call.stub->CloseSession(&call.context, RefOf(call), &r);
  if (!s.ok()) return ReportFailure(s);
  std::printf("closed %s\n", call.id.c_str());
  return 0;
}

hapsim::viewer::CompactMesh MeshOf(const hapsim::v1::MeshSnapshot& snap) {
  hapsim::viewer::CompactMesh mesh;
  mesh.vertices_m = Eigen::Map<const Eigen::Matrix3Xd>(snap.positions_m().data(), 3, snap.positions_m_size() / 3);
  mesh.triangles.assign(snap.triangles().begin(), snap.triangles().end());
  for (const auto p : snap.triangle_parts()) mesh.triangle_parts.push_back(static_cast<std::uint16_t>(p));
  mesh.part_names.assign(snap.part_names().begin(), snap.part_names().end());
  if (mesh.triangle_parts.size() * 3 != mesh.triangles.size()) mesh.part_names.clear();  // an older server: one group
  return mesh;
}

int RunSnapshot(CommandCall& call) {
  const bool as_obj = !call.flags.obj.empty();  // --obj FILE: OBJ whatever the extension
  const std::string file = as_obj ? call.flags.obj : call.flags.export_file;
  if (file.empty() || (as_obj && !call.flags.export_file.empty())) {
    std::fprintf(stderr, "hapsim-ctl: snapshot ID --obj FILE | --export FILE\n");
    return 2;
  }
  hapsim::v1::MeshSnapshot snap;
  const auto s = call.stub->GetSnapshot(&call.context, RefOf(call), &snap);
  if (!s.ok()) return ReportFailure(s);
  const std::string comment = "hapsim snapshot of " + call.id + " at sim time " + std::to_string(snap.sim_time_s());
  std::string error;
  const bool written = as_obj ? hapsim::viewer::WriteObj(file, MeshOf(snap), comment)
                              : hapsim::viewer::WriteMeshFile(file, MeshOf(snap), comment, &error);
  if (!written) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", as_obj ? ("cannot write " + file).c_str() : error.c_str());
    return 1;
  }
  std::printf("wrote %s: %d vertices, %d triangles, sim time %.3f s\n", file.c_str(), snap.positions_m_size() / 3,
              snap.triangles_size() / 3, snap.sim_time_s());
  return 0;
}

int RunScore(CommandCall& call) {
  hapsim::v1::SubmitScoresRequest req;
  req.set_session_id(call.id);
  req.set_expert(call.flags.expert);
  if (!ParseIndicators(call.flags.indicators, &req)) {
    std::fprintf(stderr, "hapsim-ctl: score ID --indicators a,b,c,d,e,f,g [--expert NAME]\n");
    return 2;
  }
  hapsim::v1::ScoreReport r;
  const auto s = call.stub->SubmitScores(&call.context, req, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintScores(r);
  return 0;
}

int RunScores(CommandCall& call) {
  hapsim::v1::ScoreQuery q;
  q.set_session_id(call.id);
  hapsim::v1::ScoreReport r;
  const auto s = call.stub->GetScores(&call.context, q, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintScores(r);
  return 0;
}

int RunJoin(CommandCall& call) {
  hapsim::v1::JoinSessionResponse r;
  const auto s = call.stub->JoinSession(&call.context, RefOf(call), &r);
  if (!s.ok()) return ReportFailure(s);
  std::printf("session=%s scene=%s dds_domain=%u dds_partition=%s\n", r.session_id().c_str(), r.scene().c_str(),
              r.dds_domain(), r.dds_partition().c_str());
  std::printf("start the device with: hapsim-bridge --session %s --dds-domain %u\n", r.session_id().c_str(),
              r.dds_domain());
  return 0;
}

int RunLocate(CommandCall& call) {
  hapsim::v1::LocateRequest req;
  req.set_session_id(call.id);
  hapsim::v1::LocateResponse r;
  const auto s = call.stub->Locate(&call.context, req, &r);
  for (const auto& u : r.unreachable()) std::fprintf(stderr, "hapsim-ctl: did not answer: %s\n", u.c_str());
  if (!s.ok()) return ReportFailure(s);
  std::printf("session=%s server=%s address=%s on_this_server=%s class=%s\n", r.session_id().c_str(),
              r.server_name().empty() ? "-" : r.server_name().c_str(), r.address().empty() ? "-" : r.address().c_str(),
              r.on_this_server() ? "yes" : "no", r.class_name().empty() ? "-" : r.class_name().c_str());
  for (const auto& other : r.also_on()) {
    std::fprintf(stderr, "hapsim-ctl: warning: the same session id is also on %s\n", other.c_str());
  }
  return 0;
}

int RunTrials(CommandCall& call) {
  hapsim::v1::TrialQuery q;
  q.set_class_name(call.id);
  hapsim::v1::TrialReport r;
  const auto s = call.stub->GetTrials(&call.context, q, &r);
  if (!s.ok()) return ReportFailure(s);
  const std::string& file = call.flags.csv;
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

int RunPush(CommandCall& call) {
  hapsim::v1::PushScenarioRequest req;
  req.set_class_name(call.id);
  req.set_scene(call.flags.scene);
  if (!AddParams(call.flags.params, req.mutable_params())) return 2;
  hapsim::v1::PushScenarioResponse r;
  const auto s = call.stub->PushScenario(&call.context, req, &r);
  if (!s.ok()) return ReportFailure(s);
  for (const auto& i : r.sessions()) PrintInfo(i);
  std::printf("pushed %s to %d sessions\n", req.scene().empty() ? "tissue_block" : req.scene().c_str(),
              r.sessions_size());
  return 0;
}

}  // namespace

int ReportFailure(const grpc::Status& status) {
  std::fprintf(stderr, "hapsim-ctl: %s (%d)\n", status.error_message().c_str(), static_cast<int>(status.error_code()));
  return 1;
}

const Command* FindCommand(const std::string& name) {
  static const std::map<std::string, Command> commands = {
      {"scenes", {IdArg::kNone, &RunScenes}},
      {"list", {IdArg::kNone, &RunList}},
      {"create", {IdArg::kOptionalId, &RunCreate}},
      {"health", {IdArg::kNone, &RunHealth}},
      {"locate", {IdArg::kOneId, &RunLocate}},
      {"info", {IdArg::kOneId, &RunSessionControl, true}},
      {"close", {IdArg::kOneId, &RunClose, true}},
      {"pause", {IdArg::kOneId, &RunSessionControl, true}},
      {"resume", {IdArg::kOneId, &RunSessionControl, true}},
      {"reset", {IdArg::kOneId, &RunSessionControl, true}},
      {"snapshot", {IdArg::kOneId, &RunSnapshot, true}},
      {"score", {IdArg::kOneId, &RunScore, true}},
      {"join", {IdArg::kOneId, &RunJoin, true}},
      {"scores", {IdArg::kOptionalId, &RunScores}},
      {"watch", {IdArg::kOptionalId, &Watch}},
      {"trials", {IdArg::kOptionalId, &RunTrials}},
      {"push", {IdArg::kOneId, &RunPush}},
      {"recordings", {IdArg::kOptionalId, &RunRecordings}},
      {"fetch-recording", {IdArg::kOneId, &RunFetchRecording}},
      {"delete-recording", {IdArg::kOneId, &RunDeleteRecording}},
      {"replay", {IdArg::kOneId, &RunReplay}},
      {"replay-info", {IdArg::kOneId, &RunReplayInfo, true}},
      {"step", {IdArg::kOneId, &RunStep, true}},
      {"seek", {IdArg::kOneId, &RunSeek, true}},
  };
  const auto it = commands.find(name);
  return it == commands.end() ? nullptr : &it->second;
}

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
  if (command == "fetch-recording") f->Add("output", &c->output, "write it to this file (empty: its name in the id)");
  if (command == "replay") {
    f->Add("speed", &c->speed, "multiple of real time, [0.1, 10] (empty: 1)");
    f->Add("start-s", &c->start_s, "start this far into the trial [s] (empty: its start)");
    f->Add("paused", &c->paused, "open it paused (then step, or resume)");
  }
  if (command == "step") f->Add("ticks", &c->ticks, "recorded ticks to play, [1, 100000] (empty: 1)");
  if (command == "seek") f->Add("to-s", &c->to_s, "where to go in the trial [s]");
}

}  // namespace hapsim::ctl
