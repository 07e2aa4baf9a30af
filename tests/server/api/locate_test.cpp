// SessionService.Locate on a site of several servers, each a real ServerApp
// on loopback with the same directory: a session is found on whichever
// server runs it, asking any of them; a server that is down or hangs makes
// only its own sessions unavailable, within the peer timeout; every server
// judges its own tokens.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/app/server_app.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "test_dds_domain.h"

namespace hapsim::service {
namespace {

using namespace std::chrono_literals;

// A loopback TCP socket bound to a free port, which no server can take
// while it is open: listening (the kernel accepts connections nobody
// serves: a peer that never answers) or not (connections are refused: a
// server that is down).
class LoopbackPort {
 public:
  explicit LoopbackPort(bool listening) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    socklen_t size = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &size);
    port_ = ntohs(a.sin_port);
    if (listening) {
      EXPECT_EQ(::listen(fd_, 16), 0);
    }
  }
  ~LoopbackPort() { Close(); }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }

 private:
  int fd_;
  int port_ = 0;
};

// Two plain classes with a trainee token each: server a runs class "ca"
// (sessions a1, dup), server b class "cb" (b1, dup).
ClassConfig ClassOf(const std::string& server) {
  const std::string c = "c" + server, s = server + "1";
  return ParseClassConfig("[[class]]\nname = \"" + c + "\"\n[[class.session]]\nid = \"" + s +
                              "\"\n[[class.session]]\nid = \"dup\"\n[[token]]\nname = \"trainee-" + server +
                              "\"\nrole = \"trainee\"\nclass = \"" + c + "\"\nsessions = [\"" + s +
                              "\"]\ntoken = \"token-of-trainee-" + server + "\"\n",
                          "test");
}

class LocateTest : public ::testing::Test {
 protected:
  // Servers a and b, and a third directory entry c: a live server when
  // third_address is empty, else that address (down or hung).
  void StartSite(bool with_classes, const std::string& third_address, std::chrono::milliseconds peer_timeout = 300ms) {
    // Held open together, so the three ports differ.
    LoopbackPort port_a(false), port_b(false), port_c(false);
    addresses_ = {port_a.address(), port_b.address(), third_address.empty() ? port_c.address() : third_address};
    port_a.Close();
    port_b.Close();
    port_c.Close();
    ServerDirectory directory;
    directory.servers = {{"a", addresses_[0]}, {"b", addresses_[1]}, {"c", addresses_[2]}};
    const std::uint32_t domain = test::ClaimTestDdsDomain();
    for (const std::string name : {"a", "b", "c"}) {
      if (name == "c" && !third_address.empty()) break;
      ServerOptions o;
      o.listen_address = directory.Find(name)->address;
      o.dds.domain_id = domain;
      o.directory = DirectoryOptions{directory, name, "", peer_timeout};
      if (with_classes) o.classes = ClassOf(name);
      apps_.push_back(std::make_unique<ServerApp>(o));
      if (!with_classes) apps_.back()->registry().Create(name + "1", "tissue_block", "", {});
    }
  }
  void TearDown() override {
    for (auto& app : apps_) app->Shutdown();
  }

  // Locate asked of server `asked` (0: a, 1: b).
  grpc::Status Locate(int asked, const std::string& id, hapsim::v1::LocateResponse* out, const std::string& token = "",
                      bool local_only = false) {
    auto stub =
        hapsim::v1::SessionService::NewStub(grpc::CreateChannel(addresses_[asked], grpc::InsecureChannelCredentials()));
    grpc::ClientContext ctx;
    ctx.set_deadline(std::chrono::system_clock::now() + 10s);
    if (!token.empty()) ctx.AddMetadata("authorization", "Bearer " + token);
    hapsim::v1::LocateRequest req;
    req.set_session_id(id);
    req.set_local_only(local_only);
    return stub->Locate(&ctx, req, out);
  }

  std::vector<std::string> addresses_;
  std::vector<std::unique_ptr<ServerApp>> apps_;
};

TEST_F(LocateTest, ASessionIsFoundOnTheServerThatRunsItWhicheverServerIsAsked) {
  const LoopbackPort down(false);  // bound, not listening: connections are refused
  const std::string down_address = down.address();
  StartSite(false, down_address);
  for (int asked : {0, 1}) {
    for (const std::string id : {"a1", "b1"}) {
      hapsim::v1::LocateResponse r;
      ASSERT_TRUE(Locate(asked, id, &r).ok()) << id << " asked of " << asked;
      const int host = id == "a1" ? 0 : 1;
      EXPECT_EQ(r.session_id(), id);
      EXPECT_EQ(r.server_name(), host == 0 ? "a" : "b");
      EXPECT_EQ(r.address(), addresses_[host]);
      EXPECT_EQ(r.on_this_server(), host == asked);
      // Found on a server that answered: the one that is down is not named.
      EXPECT_EQ(r.unreachable_size(), host == asked ? 0 : 1);
    }
  }
}

TEST_F(LocateTest, AServerThatIsDownMakesOnlyUnknownIdsUnavailableAndIsNamed) {
  const LoopbackPort down(false);  // bound, not listening: connections are refused
  const std::string down_address = down.address();
  StartSite(false, down_address);
  hapsim::v1::LocateResponse r;
  const auto status = Locate(0, "c1", &r);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_NE(status.error_message().find("session 'c1' is on no server that answered; these did not: c (" +
                                        down_address + ")"),
            std::string::npos)
      << status.error_message();
}

TEST_F(LocateTest, AServerThatHangsCostsALocateNoMoreThanThePeerTimeout) {
  LoopbackPort hung(true);  // accepts TCP, never speaks HTTP/2
  StartSite(false, hung.address(), 300ms);
  hapsim::v1::LocateResponse r;
  const auto start = std::chrono::steady_clock::now();
  const auto status = Locate(0, "c1", &r);
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  EXPECT_NE(status.error_message().find("c (" + hung.address() + ")"), std::string::npos) << status.error_message();
  // 300 ms for the hung peer, plus the call's own loopback round trips (well under 200 ms here).
  EXPECT_GE(elapsed, 290ms);
  EXPECT_LT(elapsed, 500ms) << std::chrono::duration<double>(elapsed).count() << " s";
  // A session of a live server is still found in the meantime.
  ASSERT_TRUE(Locate(0, "b1", &r).ok());
  EXPECT_EQ(r.server_name(), "b");
}

TEST_F(LocateTest, AnIdNoServerHasIsNotFoundAndAPeerIsAskedForItsOwnSessionsOnly) {
  StartSite(false, "");
  hapsim::v1::LocateResponse r;
  const auto nowhere = Locate(0, "z1", &r);
  EXPECT_EQ(nowhere.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(nowhere.error_message(), "no session 'z1' on any of the 3 servers of the directory");
  // local_only, as servers ask each other: b1 is on b, not on a.
  const auto here_only = Locate(0, "b1", &r, "", /*local_only=*/true);
  EXPECT_EQ(here_only.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(here_only.error_message(), "no session 'b1' on this server");
  EXPECT_EQ(Locate(0, "no such id", &r).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(LocateTest, EachServerJudgesItsOwnTokens) {
  const LoopbackPort down(false);  // bound, not listening: connections are refused
  const std::string down_address = down.address();
  StartSite(true, down_address);
  hapsim::v1::LocateResponse r;
  // b's trainee asks a, which does not know the token: b knows it and answers.
  ASSERT_TRUE(Locate(0, "b1", &r, "token-of-trainee-b").ok());
  EXPECT_EQ(r.server_name(), "b");
  EXPECT_EQ(r.class_name(), "cb");
  // a's trainee may not learn where b's session is: b refuses its token.
  auto status = Locate(0, "b1", &r, "token-of-trainee-a");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << status.error_message();
  EXPECT_NE(status.error_message().find("server b refused"), std::string::npos) << status.error_message();
  // On its own server, a token that may not view the session is refused as any call is.
  status = Locate(1, "b1", &r, "token-of-trainee-a");
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  status = Locate(0, "dup", &r, "token-of-trainee-a");  // a's class session, not the trainee's
  EXPECT_EQ(status.error_code(), grpc::StatusCode::PERMISSION_DENIED) << status.error_message();
}

TEST_F(LocateTest, OneIdOnTwoServersIsReportedSoTheSiteCanBeFixed) {
  StartSite(false, "");
  apps_[1]->registry().Create("dup", "tissue_block", "", {});
  apps_[2]->registry().Create("dup", "tissue_block", "", {});
  hapsim::v1::LocateResponse r;
  ASSERT_TRUE(Locate(0, "dup", &r).ok());
  EXPECT_EQ(r.server_name(), "b");  // the first in the directory's order
  ASSERT_EQ(r.also_on_size(), 1);
  EXPECT_EQ(r.also_on(0), "c (" + addresses_[2] + ")");
}

}  // namespace
}  // namespace hapsim::service
