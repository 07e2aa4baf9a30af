// The role matrix through the real server: every SessionService and
// ViewerService RPC x every caller (instructor, trainee, observer, no token,
// garbage token) x every target (own session, another session of the class,
// a session of another class) -> the status the role table in
// access_policy.h promises. Prints the matrix it saw.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/app/server_app.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/v1/viewer.grpc.pb.h"
#include "test_dds_domain.h"

namespace hapsim::service {
namespace {

using namespace std::chrono_literals;
using grpc::StatusCode;

constexpr const char* kConfig = R"(
[[class]]
name = "a"
[[class.session]]
id = "t1"
trainee = "alice"
[[class.session]]
id = "t2"
trainee = "bob"

[[class]]
name = "b"
[[class.session]]
id = "u1"

[[token]]
name = "dr-a"
role = "instructor"
class = "a"
token = "instructor-token-aaaa"

[[token]]
name = "alice"
role = "trainee"
class = "a"
sessions = ["t1"]
token = "trainee-token-alice1"

[[token]]
name = "watcher"
role = "observer"
class = "a"
token = "observer-token-watch"
)";

enum class Caller { kInstructor, kTrainee, kObserver, kNone, kGarbage };
constexpr const char* kCallerNames[] = {"instructor", "trainee", "observer", "no token", "garbage"};
const char* kTokens[] = {"instructor-token-aaaa", "trainee-token-alice1", "observer-token-watch", nullptr,
                         "Zm9vYmFy-not-a-token"};
// Targets: the trainee's own session, another session of the same class,
// a session of another class (for class RPCs: own class, own class, other class).
constexpr const char* kSessionTargets[] = {"t1", "t2", "u1"};
constexpr const char* kClassTargets[] = {"a", "a", "b"};
constexpr const char* kTargetNames[] = {"own", "class", "other class"};

class AccessMatrixTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spdlog::set_level(spdlog::level::warn);  // the printed matrix stays readable
    ServerOptions o;
    o.listen_address = "127.0.0.1:0";
    o.dds.domain_id = test::ClaimTestDdsDomain();
    o.classes = ParseClassConfig(kConfig, "test");
    app_ = std::make_unique<ServerApp>(o);
    auto channel =
        grpc::CreateChannel("127.0.0.1:" + std::to_string(app_->bound_port()), grpc::InsecureChannelCredentials());
    sessions_ = v1::SessionService::NewStub(channel);
    viewers_ = v1::ViewerService::NewStub(channel);
  }
  void TearDown() override {
    app_->Shutdown();
    spdlog::set_level(spdlog::level::info);
  }

  static void Prepare(grpc::ClientContext* ctx, Caller who) {
    ctx->set_deadline(std::chrono::system_clock::now() + 10s);
    if (const char* t = kTokens[static_cast<int>(who)]) ctx->AddMetadata("authorization", std::string("Bearer ") + t);
  }
  // The registry's view, for restoring what an allowed call changed.
  void EnsureSession(const std::string& id) {
    if (app_->registry().Find(id)) return;
    app_->registry().Create(id, "tissue_block", "", {});
  }
  void Submit(const std::string& id) {
    grpc::ClientContext ctx;
    Prepare(&ctx, Caller::kInstructor);
    v1::SubmitScoresRequest req;
    req.set_session_id(id);
    for (int j = 0; j < 7; ++j) req.add_indicators(5.0);
    v1::ScoreReport report;
    ASSERT_TRUE(sessions_->SubmitScores(&ctx, req, &report).ok());
  }

  StatusCode Call(const std::string& rpc, Caller who, int target) {
    const std::string id = kSessionTargets[target];
    grpc::ClientContext ctx;
    Prepare(&ctx, who);
    v1::SessionRef ref;
    ref.set_session_id(id);
    v1::SessionInfo info;
    grpc::Status s;
    if (rpc == "ListScenes") {
      v1::ListScenesResponse r;
      s = sessions_->ListScenes(&ctx, {}, &r);
    } else if (rpc == "ListSessions") {
      v1::ListSessionsResponse r;
      s = sessions_->ListSessions(&ctx, {}, &r);
      // Filtered: a trainee sees only t1, instructor and observer t1 and t2, never u1.
      if (s.ok()) {
        const int expected = who == Caller::kTrainee ? 1 : 2;
        EXPECT_EQ(r.sessions_size(), expected) << kCallerNames[static_cast<int>(who)];
      }
    } else if (rpc == "GetSession") {
      s = sessions_->GetSession(&ctx, ref, &info);
    } else if (rpc == "CreateSession") {
      if (app_->registry().Find(id)) app_->registry().Close(id);
      v1::CreateSessionRequest req;
      req.set_session_id(id);
      s = sessions_->CreateSession(&ctx, req, &info);
      EnsureSession(id);
    } else if (rpc == "CloseSession") {
      v1::CloseSessionResponse r;
      s = sessions_->CloseSession(&ctx, ref, &r);
      EnsureSession(id);
    } else if (rpc == "PauseSession") {
      s = sessions_->PauseSession(&ctx, ref, &info);
    } else if (rpc == "ResumeSession") {
      s = sessions_->ResumeSession(&ctx, ref, &info);
    } else if (rpc == "ResetSession") {
      s = sessions_->ResetSession(&ctx, ref, &info);
    } else if (rpc == "GetSnapshot") {
      v1::MeshSnapshot snap;
      s = sessions_->GetSnapshot(&ctx, ref, &snap);
      for (int retry = 0; s.error_code() == StatusCode::FAILED_PRECONDITION && retry < 50; ++retry) {
        std::this_thread::sleep_for(20ms);  // a re-created session has no snapshot for a frame
        grpc::ClientContext again;
        Prepare(&again, who);
        s = sessions_->GetSnapshot(&again, ref, &snap);
      }
    } else if (rpc == "SubmitScores") {
      v1::SubmitScoresRequest req;
      req.set_session_id(id);
      req.set_expert("matrix");
      for (int j = 0; j < 7; ++j) req.add_indicators(6.0);
      v1::ScoreReport r;
      s = sessions_->SubmitScores(&ctx, req, &r);
    } else if (rpc == "GetScores") {
      v1::ScoreQuery q;
      q.set_session_id(id);
      v1::ScoreReport r;
      s = sessions_->GetScores(&ctx, q, &r);
    } else if (rpc == "JoinSession") {
      v1::JoinSessionResponse r;
      s = sessions_->JoinSession(&ctx, ref, &r);
      if (s.ok()) {
        EXPECT_EQ(r.dds_partition(), "hapsim_s_" + id);
      }
    } else if (rpc == "WatchClass") {
      v1::WatchClassRequest req;
      req.set_class_name(kClassTargets[target]);
      auto reader = sessions_->WatchClass(&ctx, req);
      v1::ClassStatus status;
      if (reader->Read(&status)) {
        EXPECT_EQ(status.sessions_size() + status.missing_sessions_size(), 2);
        ctx.TryCancel();
        (void)reader->Finish();
        return StatusCode::OK;
      }
      s = reader->Finish();
    } else if (rpc == "GetTrials") {
      v1::TrialQuery q;
      q.set_class_name(kClassTargets[target]);
      v1::TrialReport r;
      s = sessions_->GetTrials(&ctx, q, &r);
      if (s.ok()) {
        EXPECT_GE(r.trials(), 2u);  // at least the running trials of t1 and t2
      }
    } else if (rpc == "PushScenario") {
      v1::PushScenarioRequest req;
      req.set_class_name(kClassTargets[target]);
      req.set_scene("tissue_block");
      v1::PushScenarioResponse r;
      s = sessions_->PushScenario(&ctx, req, &r);
    } else if (rpc == "Subscribe") {
      auto stream = viewers_->Subscribe(&ctx);
      v1::ViewerMessage hello;
      hello.mutable_subscribe()->set_session_id(id);
      stream->Write(hello);
      v1::Frame frame;
      if (stream->Read(&frame)) {
        ctx.TryCancel();
        (void)stream->Finish();
        return StatusCode::OK;
      }
      s = stream->Finish();
    } else {
      ADD_FAILURE() << "unknown rpc " << rpc;
    }
    return s.error_code();
  }

  std::unique_ptr<ServerApp> app_;
  std::unique_ptr<v1::SessionService::Stub> sessions_;
  std::unique_ptr<v1::ViewerService::Stub> viewers_;
};

// What access_policy.h's table promises.
StatusCode Expected(const std::string& rpc, Caller who, int target) {
  if (who == Caller::kNone || who == Caller::kGarbage) return StatusCode::UNAUTHENTICATED;
  const bool own = target == 0, in_class = target < 2;
  auto allow = [](bool ok) { return ok ? StatusCode::OK : StatusCode::PERMISSION_DENIED; };
  if (rpc == "ListScenes" || rpc == "ListSessions") return StatusCode::OK;
  if (rpc == "GetSession" || rpc == "GetSnapshot" || rpc == "GetScores" || rpc == "Subscribe") {
    return allow(who == Caller::kTrainee ? own : in_class);
  }
  if (rpc == "JoinSession") {
    return allow(who == Caller::kTrainee ? own : who == Caller::kInstructor && in_class);
  }
  if (rpc == "WatchClass" || rpc == "GetTrials") return allow(who != Caller::kTrainee && in_class);
  // Create, Close, Pause, Resume, Reset, SubmitScores, PushScenario
  return allow(who == Caller::kInstructor && in_class);
}

TEST_F(AccessMatrixTest, EveryRpcRoleAndTargetGetsThePromisedStatus) {
  std::this_thread::sleep_for(100ms);  // first snapshots
  Submit("t1");
  Submit("t2");
  const std::vector<std::string> rpcs = {
      "ListScenes",   "ListSessions", "GetSession",   "CreateSession", "CloseSession", "PauseSession",
      "ResumeSession", "ResetSession", "GetSnapshot", "SubmitScores",  "GetScores",    "JoinSession",
      "WatchClass",   "GetTrials",    "PushScenario", "Subscribe"};
  int checked = 0, wrong = 0;
  std::printf("%-14s", "rpc \\ caller");
  for (const char* c : kCallerNames) std::printf(" | %-26s", c);
  std::printf("\n%-14s", "");
  for (int c = 0; c < 5; ++c) std::printf(" | %-8s %-8s %-8s", kTargetNames[0], kTargetNames[1], "other");
  std::printf("\n");
  for (const auto& rpc : rpcs) {
    std::printf("%-14s", rpc.c_str());
    for (int c = 0; c < 5; ++c) {
      std::printf(" |");
      for (int t = 0; t < 3; ++t) {
        const auto who = static_cast<Caller>(c);
        const StatusCode got = Call(rpc, who, t);
        const StatusCode want = Expected(rpc, who, t);
        ++checked;
        const char* shown = got == StatusCode::OK                  ? "ok"
                            : got == StatusCode::PERMISSION_DENIED ? "denied"
                            : got == StatusCode::UNAUTHENTICATED   ? "unauth"
                                                                   : "OTHER";
        std::printf(" %-7s%s", shown, got == want ? " " : "!");
        if (got != want) {
          ++wrong;
          ADD_FAILURE() << rpc << " by " << kCallerNames[c] << " on " << kTargetNames[t] << ": got code "
                        << static_cast<int>(got) << ", want " << static_cast<int>(want);
        }
      }
    }
    std::printf("\n");
  }
  std::printf("%d cells checked, %d wrong\n", checked, wrong);
  EXPECT_EQ(checked, 16 * 5 * 3);
  // Every refusal was counted for /metrics.
  EXPECT_GT(app_->policy().counters().unauthenticated.load(), 0u);
  EXPECT_GT(app_->policy().counters().permission_denied.load(), 0u);
}

// Row 86 of docs/reliability.md: a class view asked at a rate outside
// [0.1, 50] Hz is refused before it holds anything, and a 17th view while
// 16 are open is RESOURCE_EXHAUSTED naming the limit (each holds a server
// thread); closing one frees its place.
TEST_F(AccessMatrixTest, AClassViewOutsideTheRateRangeOrPastTheLimitIsRefused) {
  const auto watch = [&](grpc::ClientContext* ctx, double rate_hz) {
    Prepare(ctx, Caller::kInstructor);
    v1::WatchClassRequest req;
    req.set_class_name("a");
    req.set_rate_hz(rate_hz);
    return sessions_->WatchClass(ctx, req);
  };
  for (const double bad : {0.05, 50.5, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    grpc::ClientContext ctx;
    auto reader = watch(&ctx, bad);
    v1::ClassStatus status;
    EXPECT_FALSE(reader->Read(&status)) << bad;
    const auto finished = reader->Finish();
    EXPECT_EQ(finished.error_code(), StatusCode::INVALID_ARGUMENT) << bad;
    EXPECT_NE(finished.error_message().find("rate_hz must be 0 (10 Hz) or within [0.1, 50]"), std::string::npos);
  }
  constexpr int kLimit = SessionServiceImpl::kMaxWatchStreams;
  std::vector<std::unique_ptr<grpc::ClientContext>> open_ctx;
  std::vector<std::unique_ptr<grpc::ClientReader<v1::ClassStatus>>> open;
  for (int k = 0; k < kLimit; ++k) {
    open_ctx.push_back(std::make_unique<grpc::ClientContext>());
    open.push_back(watch(open_ctx.back().get(), 0.0));
    v1::ClassStatus first;
    ASSERT_TRUE(open.back()->Read(&first)) << "view " << k;  // the server counts it once it writes
  }
  {
    grpc::ClientContext ctx;
    auto reader = watch(&ctx, 0.0);
    v1::ClassStatus status;
    EXPECT_FALSE(reader->Read(&status));
    const auto finished = reader->Finish();
    EXPECT_EQ(finished.error_code(), StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(finished.error_message().find("already serves 16 class views"), std::string::npos)
        << finished.error_message();
  }
  open_ctx.front()->TryCancel();  // the instructor closes one view
  open.front()->Finish();
  bool reopened = false;
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (!reopened && std::chrono::steady_clock::now() < until) {
    grpc::ClientContext ctx;
    auto reader = watch(&ctx, 0.0);
    v1::ClassStatus status;
    reopened = reader->Read(&status);
    ctx.TryCancel();
    reader->Finish();
    if (!reopened) std::this_thread::sleep_for(50ms);
  }
  EXPECT_TRUE(reopened) << "a closed view's place was not freed";
  for (std::size_t k = 1; k < open.size(); ++k) {
    open_ctx[k]->TryCancel();
    open[k]->Finish();
  }
}

// Row 87: a scenario the class cannot run (unknown scene, unknown or
// non-finite parameter) is refused with the reason before any session of
// the class is closed or rebuilt.
TEST_F(AccessMatrixTest, ABadPushedScenarioIsRefusedSayingWhyAndTouchesNoSession) {
  EnsureSession("t1");
  EnsureSession("t2");
  const auto t1 = app_->registry().Find("t1");
  const auto t2 = app_->registry().Find("t2");
  struct Case {
    const char* scene;
    const char* key;
    double value;
    const char* reason;
  };
  for (const Case& c : {Case{"no_such_scene", nullptr, 0.0, "no_such_scene"},
                        Case{"tissue_block", "no_such_param", 1.0, "no_such_param"},
                        Case{"tissue_block", "grid_nodes", std::nan(""), "scene parameter 'grid_nodes' is not finite"}}) {
    grpc::ClientContext ctx;
    Prepare(&ctx, Caller::kInstructor);
    v1::PushScenarioRequest req;
    req.set_class_name("a");
    req.set_scene(c.scene);
    if (c.key) (*req.mutable_params())[c.key] = c.value;
    v1::PushScenarioResponse out;
    const auto status = sessions_->PushScenario(&ctx, req, &out);
    EXPECT_EQ(status.error_code(), StatusCode::INVALID_ARGUMENT) << c.scene;
    EXPECT_NE(status.error_message().find(c.reason), std::string::npos) << status.error_message();
    EXPECT_EQ(out.sessions_size(), 0);
    EXPECT_EQ(app_->registry().Find("t1"), t1) << "t1 was rebuilt";
    EXPECT_EQ(app_->registry().Find("t2"), t2) << "t2 was rebuilt";
  }
}

}  // namespace
}  // namespace hapsim::service
