// The browser console's endpoint through a real server (ServerApp with a
// class config) and a WebSocket client: the hello's token is checked and a
// refusal counted, every action is decided by the server's access policy
// (an observer cannot reset, a trainee sees only their own session), the
// class view and the trainee view stream what gRPC's do, bad input closes
// only its own connection, and the web app's files are served and nothing
// outside them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <boost/beast/http.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "console_client.h"
#include "hapsim/app/server_app.h"
#include "test_dds_domain.h"

namespace hapsim::web {
namespace {

using namespace std::chrono_literals;
using hapsim::v1::ConsoleEvent;
using test::PlainClient;
using test::TlsClient;
namespace http = boost::beast::http;

constexpr const char* kClassConfig = R"(
[[class]]
name = "anatomy"
[[class.session]]
id = "t1"
scene = "tissue_block"
trainee = "ann"
[[class.session]]
id = "t2"
scene = "tissue_block"
trainee = "bob"
[[token]]
name = "dr"
role = "instructor"
class = "anatomy"
token = "instructor-token-web1"
[[token]]
name = "visitor"
role = "observer"
class = "anatomy"
token = "observer-token-web1"
[[token]]
name = "ann"
role = "trainee"
class = "anatomy"
sessions = ["t1"]
token = "trainee-token-web-ann"
)";

// A temporary web app folder: what the endpoint serves.
class WebRoot {
 public:
  WebRoot() : dir_(std::filesystem::temp_directory_path() / ("hapsim-web-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_ / "assets");
    std::ofstream(dir_ / "index.html") << "<!doctype html><title>console</title>";
    std::ofstream(dir_ / "assets" / "app.js") << "console.log(1);";
    std::ofstream(dir_.parent_path() / ("hapsim-web-secret-" + std::to_string(::getpid()))) << "secret";
  }
  ~WebRoot() {
    std::filesystem::remove_all(dir_);
    std::filesystem::remove(dir_.parent_path() / ("hapsim-web-secret-" + std::to_string(::getpid())));
  }
  std::string path() const { return dir_.string(); }

 private:
  std::filesystem::path dir_;
};

class WebConsoleTest : public ::testing::Test {
 protected:
  void Start(const std::string& cert = "", const std::string& key = "", bool with_classes = true) {
    service::ServerOptions o;
    o.listen_address = "127.0.0.1:0";
    o.dds.domain_id = hapsim::test::ClaimTestDdsDomain();
    o.web_listen_address = "127.0.0.1:0";
    o.web_root = root_.path();
    o.tls_cert_file = cert;
    o.tls_key_file = key;
    if (with_classes) o.classes = service::ParseClassConfig(kClassConfig, "test");
    app_ = std::make_unique<service::ServerApp>(o);
    port_ = app_->web_port();
    ASSERT_GT(port_, 0);
  }
  void TearDown() override {
    if (app_) app_->Shutdown();
  }

  // A connected client past its hello; the welcome in *welcome.
  std::unique_ptr<PlainClient> LoggedIn(const std::string& token, ConsoleEvent* welcome = nullptr) {
    auto client = std::make_unique<PlainClient>();
    std::string why;
    EXPECT_TRUE(client->Connect(port_, &why)) << why;
    client->Hello(token);
    auto event = client->Next();
    EXPECT_TRUE(event && event->has_welcome()) << (event ? event->DebugString() : "no answer");
    if (welcome && event) *welcome = *event;
    return client;
  }

  static hapsim::v1::ConsoleRequest Control(std::uint32_t id, const char* what, const std::string& session) {
    hapsim::v1::ConsoleRequest r;
    auto* call = r.mutable_call();
    call->set_id(id);
    if (std::string(what) == "reset") call->mutable_reset_session()->set_session_id(session);
    if (std::string(what) == "pause") call->mutable_pause_session()->set_session_id(session);
    return r;
  }

  static hapsim::v1::ConsoleRequest OpenView(const std::string& session) {
    hapsim::v1::ConsoleRequest r;
    r.mutable_open_view()->set_session_id(session);
    r.mutable_open_view()->set_ack_window(4);
    return r;
  }

  // GET target over plain HTTP: the status and body.
  std::pair<int, std::string> Get(const std::string& target) {
    boost::asio::io_context io;
    boost::beast::tcp_stream stream(io);
    boost::asio::ip::tcp::resolver resolver(io);
    stream.connect(resolver.resolve("127.0.0.1", std::to_string(port_)));
    http::request<http::empty_body> request(http::verb::get, target, 11);
    request.set(http::field::host, "localhost");
    http::write(stream, request);
    boost::beast::flat_buffer buffer;
    http::response<http::string_body> response;
    http::read(stream, buffer, response);
    return {static_cast<int>(response.result_int()), response.body()};
  }

  WebRoot root_;
  std::unique_ptr<service::ServerApp> app_;
  int port_ = 0;
};

TEST_F(WebConsoleTest, AGarbageTokenIsRefusedCountedAndClosesOnlyItsConnection) {
  Start();
  const auto before = app_->policy().counters().unauthenticated.load();
  PlainClient client;
  ASSERT_TRUE(client.Connect(port_));
  client.Hello("not-a-token");
  const auto event = client.Next();
  ASSERT_TRUE(event && event->has_refused()) << (event ? event->DebugString() : "no answer");
  EXPECT_EQ(event->refused().code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(event->refused().message(), "unknown token");
  EXPECT_FALSE(client.Next(2s)) << "the connection stays open after a refusal";
  EXPECT_EQ(app_->policy().counters().unauthenticated.load(), before + 1);
  LoggedIn("instructor-token-web1");  // the endpoint still serves others
}

TEST_F(WebConsoleTest, NothingButAHelloIsTakenFirst) {
  Start();
  PlainClient client;
  ASSERT_TRUE(client.Connect(port_));
  hapsim::v1::ConsoleRequest watch;
  watch.mutable_watch_class()->set_class_name("anatomy");
  client.Send(watch);
  const auto event = client.Next();
  ASSERT_TRUE(event && event->has_refused());
  EXPECT_EQ(event->refused().code(), grpc::StatusCode::UNAUTHENTICATED);
}

TEST_F(WebConsoleTest, BytesThatAreNoRequestCloseTheirConnectionOnly) {
  Start();
  auto good = LoggedIn("instructor-token-web1");
  PlainClient bad;
  ASSERT_TRUE(bad.Connect(port_));
  bad.SendBytes(std::string("\xff\xff\xff\xff garbage", 13));
  const auto event = bad.Next();
  ASSERT_TRUE(event && event->has_refused());
  EXPECT_EQ(event->refused().code(), grpc::StatusCode::INVALID_ARGUMENT);
  good->Send(Control(1, "pause", "t1"));
  const auto reply = good->NextOf(ConsoleEvent::kReply);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->reply().code(), 0) << reply->reply().message();
}

TEST_F(WebConsoleTest, TheWelcomeNamesTheTokensRoleAndClass) {
  Start();
  ConsoleEvent welcome;
  LoggedIn("trainee-token-web-ann", &welcome);
  EXPECT_EQ(welcome.welcome().name(), "ann");
  EXPECT_EQ(welcome.welcome().role(), "trainee");
  EXPECT_EQ(welcome.welcome().class_name(), "anatomy");
  ASSERT_EQ(welcome.welcome().sessions_size(), 1);
  EXPECT_EQ(welcome.welcome().sessions(0), "t1");
}

// Without a class config (development mode) anyone may do anything, as over
// gRPC; whatever the page sends as its token is not forwarded (a value that
// is no valid metadata must not reach gRPC).
TEST_F(WebConsoleTest, InDevelopmentModeAnyHelloIsWelcomeAndNoTokenIsForwarded) {
  Start("", "", /*with_classes=*/false);
  ConsoleEvent welcome;
  auto client = LoggedIn("not\nmetadata", &welcome);
  EXPECT_EQ(welcome.welcome().role(), "");
  client->Send(Control(3, "pause", "t1"));
  const auto reply = client->NextOf(ConsoleEvent::kReply);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->reply().code(), grpc::StatusCode::NOT_FOUND) << "no session t1 without the class config";
}

TEST_F(WebConsoleTest, AnInstructorWatchesEveryTraineeOfTheClass) {
  Start();
  auto client = LoggedIn("instructor-token-web1");
  hapsim::v1::ConsoleRequest watch;
  watch.mutable_watch_class()->set_class_name("anatomy");
  watch.mutable_watch_class()->set_rate_hz(20);
  client->Send(watch);
  std::uint64_t previous_seq = 0;
  for (int i = 0; i < 3; ++i) {
    const auto status = client->NextOf(ConsoleEvent::kClassStatus);
    ASSERT_TRUE(status);
    ASSERT_EQ(status->class_status().sessions_size(), 2);
    EXPECT_EQ(status->class_status().sessions(0).session_id(), "t1");
    EXPECT_EQ(status->class_status().sessions(0).trainee(), "ann");
    EXPECT_EQ(status->class_status().sessions(1).session_id(), "t2");
    if (i > 0) {
      EXPECT_EQ(status->class_status().seq(), previous_seq + 1);
    }
    previous_seq = status->class_status().seq();
  }
}

// The server allows 16 class views at once (each holds a server thread);
// browsers with the same token share one, so more tabs than that all watch.
TEST_F(WebConsoleTest, MoreTabsThanTheServersClassViewsAllWatchTheClass) {
  Start();
  constexpr int kTabs = 20;
  static_assert(kTabs > service::ClassroomCalls::kMaxWatchStreams);
  std::vector<std::unique_ptr<PlainClient>> tabs;
  hapsim::v1::ConsoleRequest watch;
  watch.mutable_watch_class()->set_class_name("anatomy");
  for (int i = 0; i < kTabs; ++i) {
    tabs.push_back(LoggedIn(i % 2 ? "observer-token-web1" : "instructor-token-web1"));
    tabs.back()->Send(watch);
  }
  for (int i = 0; i < kTabs; ++i) {
    const auto status = tabs[static_cast<std::size_t>(i)]->NextOf(ConsoleEvent::kClassStatus);
    ASSERT_TRUE(status) << "tab " << i;
    EXPECT_EQ(status->class_status().sessions_size(), 2) << "tab " << i;
  }
}

TEST_F(WebConsoleTest, AnObserversResetIsRefusedByTheServersPolicyAndAnInstructorsIsDone) {
  Start();
  const auto denied_before = app_->policy().counters().permission_denied.load();
  auto observer = LoggedIn("observer-token-web1");
  observer->Send(Control(7, "reset", "t1"));
  const auto refused = observer->NextOf(ConsoleEvent::kReply);
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->reply().id(), 7u);
  EXPECT_EQ(refused->reply().code(), grpc::StatusCode::PERMISSION_DENIED) << refused->reply().message();
  EXPECT_EQ(app_->policy().counters().permission_denied.load(), denied_before + 1);

  auto instructor = LoggedIn("instructor-token-web1");
  instructor->Send(Control(8, "reset", "t1"));
  const auto done = instructor->NextOf(ConsoleEvent::kReply);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->reply().code(), 0) << done->reply().message();
  EXPECT_EQ(done->reply().session().session_id(), "t1");
}

TEST_F(WebConsoleTest, ATraineeViewsTheirOwnSessionAndNoOtherOne) {
  Start();
  auto ann = LoggedIn("trainee-token-web-ann");
  ann->Send(OpenView("t2"));
  const auto ended = ann->NextOf(ConsoleEvent::kEnded);
  ASSERT_TRUE(ended);
  EXPECT_EQ(ended->ended().stream(), "view");
  EXPECT_EQ(ended->ended().code(), grpc::StatusCode::PERMISSION_DENIED);

  ann->Send(OpenView("t1"));
  const auto first = ann->NextOf(ConsoleEvent::kFrame);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->frame().seq(), 0u);
  ASSERT_TRUE(first->frame().has_keyframe());
  EXPECT_GT(first->frame().keyframe().positions_q_size(), 300);
  EXPECT_GT(first->frame().keyframe().triangles_size(), 300);
}

// Frames go one at a time per browser and only as fast as it acknowledges
// them (ack window 4): a browser that stops acknowledging gets no more than
// the window, and once it acknowledges again the frames continue in order.
TEST_F(WebConsoleTest, ATraineeViewFollowsTheBrowsersAcks) {
  Start();
  auto client = LoggedIn("instructor-token-web1");
  client->Send(OpenView("t1"));
  for (int i = 0; i < 4; ++i) {
    const auto frame = client->NextOf(ConsoleEvent::kFrame);
    ASSERT_TRUE(frame) << "frame " << i;
    EXPECT_EQ(frame->frame().seq(), static_cast<std::uint64_t>(i));
    EXPECT_EQ(frame->frame().has_delta(), i > 0);
  }
  // The window is full until an ack: within the round trip's allowance at
  // most a few more frames may come, then none.
  int extra = 0;
  while (client->NextOf(ConsoleEvent::kFrame, 400ms)) ++extra;
  EXPECT_LE(extra, 4) << "frames kept coming without acks";
}

TEST_F(WebConsoleTest, AcknowledgedFramesKeepComingAtTheFrameRate) {
  Start();
  auto client = LoggedIn("instructor-token-web1");
  client->Send(OpenView("t1"));
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < 1s) {
    const auto frame = client->NextOf(ConsoleEvent::kFrame, 1s);
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->frame().seq(), static_cast<std::uint64_t>(frames));
    ++frames;
    hapsim::v1::ConsoleRequest ack;
    ack.mutable_ack()->set_applied_seq(frame->frame().seq());
    client->Send(ack);
  }
  EXPECT_GE(frames, 40) << "the server's frame rate is 60 Hz";
}

TEST_F(WebConsoleTest, TheWebAppsFilesAreServedAndNothingOutsideThem) {
  Start();
  EXPECT_EQ(Get("/").first, 200);
  EXPECT_EQ(Get("/").second, "<!doctype html><title>console</title>");
  EXPECT_EQ(Get("/assets/app.js?v=2").second, "console.log(1);");
  EXPECT_EQ(Get("/missing.js").first, 404);
  EXPECT_EQ(Get("/../hapsim-web-secret-" + std::to_string(::getpid())).first, 404);
  EXPECT_EQ(Get("/assets/../../hapsim-web-secret-" + std::to_string(::getpid())).first, 404);
  EXPECT_EQ(Get("/%2e%2e/hapsim-web-secret-" + std::to_string(::getpid())).first, 404);
  EXPECT_EQ(Get("/assets").first, 404) << "a folder is no file";
}

class WebConsoleTlsTest : public WebConsoleTest {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("hapsim-web-tls-" + std::to_string(::getpid()));
    const std::string cmd =
        std::string("bash ") + HAPSIM_SOURCE_DIR + "/deploy/make-dev-certs.sh " + dir_.string() + " > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }
  static inline std::filesystem::path dir_;
};

TEST_F(WebConsoleTlsTest, WithTheServersCertificateTheConsoleIsWssOnly) {
  Start((dir_ / "server.pem").string(), (dir_ / "server.key").string());
  TlsClient client((dir_ / "ca.pem").string());
  std::string why;
  ASSERT_TRUE(client.Connect(port_, &why)) << why;
  client.Hello("observer-token-web1");
  const auto welcome = client.Next();
  ASSERT_TRUE(welcome && welcome->has_welcome());
  EXPECT_EQ(welcome->welcome().role(), "observer");

  PlainClient plain;
  EXPECT_FALSE(plain.Connect(port_)) << "plain WebSocket on the TLS port";
}

}  // namespace
}  // namespace hapsim::web
