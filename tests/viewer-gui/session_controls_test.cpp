// The panel's pause / resume / reset buttons: the server's answer, or its
// refusal, is what the trainee or instructor reads under the buttons, and a
// dead server is reported within the call's deadline instead of hanging the
// window (docs/reliability.md row 94).
#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "hapsim/gui/viewer_panels.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::gui {
namespace {

// A SessionService that refuses to reset (as for an observer) and pauses
// only session "t1".
class RefusingService final : public v1::SessionService::Service {
 public:
  grpc::Status ResetSession(grpc::ServerContext*, const v1::SessionRef*, v1::SessionInfo*) override {
    return {grpc::StatusCode::PERMISSION_DENIED, "role observer may not control sessions"};
  }
  grpc::Status PauseSession(grpc::ServerContext*, const v1::SessionRef* ref, v1::SessionInfo* info) override {
    if (ref->session_id() != "t1") return {grpc::StatusCode::NOT_FOUND, "no session '" + ref->session_id() + "'"};
    info->set_session_id("t1");
    return grpc::Status::OK;
  }
};

// Waits (up to `limit`) for the control's answer, polling as the render loop does.
std::string AnswerOf(SessionControls* controls, std::chrono::seconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (controls->busy() && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return controls->last_result();
}

class SessionControlsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::ServerBuilder builder;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
    builder.RegisterService(&service_);
    server_ = builder.BuildAndStart();
    ASSERT_TRUE(server_ && port_ > 0);
    connection_.address = "127.0.0.1:" + std::to_string(port_);
  }
  void TearDown() override {
    if (server_) server_->Shutdown();
  }
  RefusingService service_;
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
  viewer::Connection connection_;
};

TEST_F(SessionControlsTest, ARefusedResetShowsTheServersReason) {
  SessionControls controls(connection_);
  EXPECT_EQ(controls.last_result(), "");
  controls.Send(viewer::SessionClient::Control::kReset, "t2");
  EXPECT_EQ(AnswerOf(&controls, std::chrono::seconds(5)),
            "reset t2: PERMISSION_DENIED: role observer may not control sessions");
}

TEST_F(SessionControlsTest, AnAcceptedPauseSaysOkAndAnUnknownSessionSaysNotFound) {
  SessionControls controls(connection_);
  controls.Send(viewer::SessionClient::Control::kPause, "t1");
  EXPECT_EQ(AnswerOf(&controls, std::chrono::seconds(5)), "pause t1: ok");
  controls.Send(viewer::SessionClient::Control::kPause, "nope");
  EXPECT_EQ(AnswerOf(&controls, std::chrono::seconds(5)), "pause nope: NOT_FOUND: no session 'nope'");
}

TEST_F(SessionControlsTest, AGoneServerIsReportedWithinTheDeadlineAndNeverBlocksTheCaller) {
  server_->Shutdown();
  server_.reset();
  SessionControls controls(connection_);
  const auto start = std::chrono::steady_clock::now();
  controls.Send(viewer::SessionClient::Control::kResume, "t1");
  // Send returns at once: the render thread keeps drawing while the call runs.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(200));
  const std::string answer = AnswerOf(&controls, std::chrono::seconds(8));
  EXPECT_EQ(answer.rfind("resume t1: UNAVAILABLE", 0), 0u) << answer;  // the 5 s deadline at most
}

}  // namespace
}  // namespace hapsim::gui
