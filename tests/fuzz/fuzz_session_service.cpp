// Any bytes as any SessionService request, through the real handler: the
// first byte picks the call (the 14 unary ones and the WatchClass stream),
// the rest is parsed as its request message (an unparsable one is sent
// empty). WatchClass writes to a stream whose instructor is gone after the
// first status (so the handler returns without waiting a period). Invariants: every call answers with a
// status and throws nothing; afterwards the server is healthy (ListSessions
// answers OK with at most max_sessions sessions) — a client's mistake never
// takes it down. Sessions are closed after each input, so inputs do not
// depend on each other. No DDS: a null transport stands for it.
#include <grpcpp/server_context.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "fuzz_setup.h"
#include "hapsim/api/session_service.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/classroom/session_trials.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/runtime/tick_pool.h"
#include "hapsim/streaming/viewer_hub.h"

namespace {

using namespace hapsim;

class NullPort final : public service::SessionPort {
 public:
  bool WriteForceModel(const service::ForceModelMessage&) override { return true; }
};
class NullTransport final : public service::SessionTransport {
 public:
  std::shared_ptr<service::SessionPort> Open(const std::string&) override { return std::make_shared<NullPort>(); }
};

constexpr std::size_t kMaxSessions = 4;

struct Server {
  service::TickPool pool{1};
  NullTransport transport;
  service::ViewerHub hub;
  service::SessionRegistry registry{service::SessionDefaults{.max_sessions = kMaxSessions}, &pool, &transport, &hub,
                                    service::FollowTrials(nullptr)};
  service::ScoreBook scores;
  service::TrialBook trials;
  service::SessionServiceImpl api{&registry, &hub, &scores, nullptr, 0, &trials};
};

Server& TheServer() {
  static Server* server = new Server();  // lives for the process (the fuzzer exits without unwinding)
  return *server;
}

// A WatchClass stream whose reader is gone after the first status.
class GoneAfterOneStatus final : public grpc::ServerWriterInterface<v1::ClassStatus> {
 public:
  void SendInitialMetadata() override {}
  bool Write(const v1::ClassStatus&, grpc::WriteOptions) override {
    ++writes;
    return false;
  }
  int writes = 0;
};

void WatchClassOnce(const std::uint8_t* data, std::size_t size) {
  v1::WatchClassRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) request.Clear();
  grpc::ServerContext context;
  GoneAfterOneStatus writer;
  const grpc::Status status = TheServer().api.WatchClassOn(&context, &request, &writer);
  // Accepted: the instructor got a status first. Refused: nothing was written
  // and the reason is given.
  if (status.ok() ? writer.writes != 1 : (writer.writes != 0 || status.error_message().empty())) std::abort();
}

template <class Request, class Response, class Call>
grpc::Status Invoke(Call call, const std::uint8_t* data, std::size_t size) {
  Request request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) request.Clear();
  Response response;
  grpc::ServerContext context;
  return (TheServer().api.*call)(&context, &request, &response);
}

// HAPSIM_FUZZ_WRITE_SEEDS=DIR: one valid request of each kind.
void WriteSeeds(const std::string& dir) {
  auto write = [&](int call, const google::protobuf::Message& m) {
    std::string bytes(1, static_cast<char>(call));
    bytes += m.SerializeAsString();
    std::ofstream(dir + "/call" + std::to_string(call), std::ios::binary) << bytes;
  };
  v1::CreateSessionRequest create;
  create.set_scene("tissue_block");
  create.set_session_id("s1");
  (*create.mutable_params())["grid_nodes"] = 11;
  write(1, create);
  v1::SessionRef ref;
  ref.set_session_id("s1");
  for (int call : {3, 4, 5, 6, 7, 8}) write(call, ref);
  v1::SubmitScoresRequest scores;
  scores.set_session_id("s1");
  scores.set_expert("e");
  for (int k = 0; k < 7; ++k) scores.add_indicators(5.0 + k * 0.5);
  write(9, scores);
  v1::ScoreQuery query;
  write(10, query);
  write(11, ref);  // JoinSession
  v1::PushScenarioRequest push;
  push.set_scene("tissue_block");
  (*push.mutable_params())["grid_nodes"] = 5;
  write(12, push);
  write(13, v1::TrialQuery());
  v1::WatchClassRequest watch;
  watch.set_rate_hz(20.0);
  write(14, watch);
  write(0, v1::ListScenesRequest());
  v1::LocateRequest locate;
  locate.set_session_id("s1");
  write(15, locate);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapsim::fuzz::SetUpServiceFuzzer(&WriteSeeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  using S = service::SessionServiceImpl;
  const std::uint8_t* body = data + 1;
  const std::size_t n = size - 1;
  try {
    switch (data[0] % 16) {
      case 0: Invoke<v1::ListScenesRequest, v1::ListScenesResponse>(&S::ListScenes, body, n); break;
      case 1: Invoke<v1::CreateSessionRequest, v1::SessionInfo>(&S::CreateSession, body, n); break;
      case 2: Invoke<v1::ListSessionsRequest, v1::ListSessionsResponse>(&S::ListSessions, body, n); break;
      case 3: Invoke<v1::SessionRef, v1::SessionInfo>(&S::GetSession, body, n); break;
      case 4: Invoke<v1::SessionRef, v1::CloseSessionResponse>(&S::CloseSession, body, n); break;
      case 5: Invoke<v1::SessionRef, v1::SessionInfo>(&S::PauseSession, body, n); break;
      case 6: Invoke<v1::SessionRef, v1::SessionInfo>(&S::ResumeSession, body, n); break;
      case 7: Invoke<v1::SessionRef, v1::SessionInfo>(&S::ResetSession, body, n); break;
      case 8: Invoke<v1::SessionRef, v1::MeshSnapshot>(&S::GetSnapshot, body, n); break;
      case 9: Invoke<v1::SubmitScoresRequest, v1::ScoreReport>(&S::SubmitScores, body, n); break;
      case 10: Invoke<v1::ScoreQuery, v1::ScoreReport>(&S::GetScores, body, n); break;
      case 11: Invoke<v1::SessionRef, v1::JoinSessionResponse>(&S::JoinSession, body, n); break;
      case 12: Invoke<v1::PushScenarioRequest, v1::PushScenarioResponse>(&S::PushScenario, body, n); break;
      case 13: Invoke<v1::TrialQuery, v1::TrialReport>(&S::GetTrials, body, n); break;
      case 14:
        WatchClassOnce(body, n);
        break;
      default:
        Invoke<v1::LocateRequest, v1::LocateResponse>(&S::Locate, body, n);
        break;
    }
  } catch (...) {
    std::abort();  // a handler let an exception out: the gRPC thread would die
  }
  // Healthy: the registry answers and respects its limit.
  v1::ListSessionsRequest list;
  v1::ListSessionsResponse sessions;
  grpc::ServerContext context;
  if (!TheServer().api.ListSessions(&context, &list, &sessions).ok()) std::abort();
  if (static_cast<std::size_t>(sessions.sessions_size()) > kMaxSessions) std::abort();
  TheServer().registry.CloseAll();
  return 0;
}
