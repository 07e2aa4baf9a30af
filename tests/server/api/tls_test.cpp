// gRPC over TLS with certificates from the shipped development-CA script
// (deploy/make-dev-certs.sh): a client trusting that CA gets through (with its
// token checked as over plain TCP); a client that does not trust it, or
// speaks plain TCP, is refused; with --tls-client-ca the server refuses a
// client without a certificate of that CA.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hapsim/app/server_app.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "test_dds_domain.h"

namespace hapsim::service {
namespace {

using namespace std::chrono_literals;

std::string Read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class TlsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("hapsim-tls-" + std::to_string(::getpid()));
    const std::string cmd = std::string("bash ") + HAPSIM_SOURCE_DIR + "/deploy/make-dev-certs.sh " + dir_.string() +
                            " > /dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    // A second, unrelated CA: what a client trusting the wrong authority holds.
    const std::string other = std::string("bash ") + HAPSIM_SOURCE_DIR + "/deploy/make-dev-certs.sh " +
                              (dir_ / "other").string() + " > /dev/null";
    ASSERT_EQ(std::system(other.c_str()), 0);
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  void Start(bool require_client_cert) {
    ServerOptions o;
    o.listen_address = "127.0.0.1:0";
    o.dds.domain_id = test::ClaimTestDdsDomain();
    o.tls_cert_file = (dir_ / "server.pem").string();
    o.tls_key_file = (dir_ / "server.key").string();
    if (require_client_cert) o.tls_client_ca_file = (dir_ / "ca.pem").string();
    o.classes = ParseClassConfig(R"(
[[class]]
name = "c"
[[class.session]]
id = "t1"
[[token]]
name = "dr"
role = "instructor"
class = "c"
token = "instructor-token-tls1"
)",
                                 "test");
    app_ = std::make_unique<ServerApp>(o);
  }
  void TearDown() override {
    if (app_) app_->Shutdown();
  }

  // A call that must reach the server waits for the channel to connect
  // (gRPC retries a failed connect after 100 ms): Debian's gRPC 1.51 reads
  // errno late after a non-blocking connect(), and a thread of the
  // in-process server that touched an absl::Mutex first in that window left
  // ENOENT there — a fail-fast first call then failed with "No such file or
  // directory" (seen once on a fresh machine). Calls expected to be refused
  // at the handshake stay fail-fast: they must end UNAVAILABLE.
  enum class Reach { kMustReachServer, kMayBeRefused };
  grpc::Status List(const std::shared_ptr<grpc::ChannelCredentials>& credentials, const char* token,
                    v1::ListSessionsResponse* out, Reach reach = Reach::kMustReachServer) {
    grpc::ChannelArguments args;
    args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
    args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
    auto channel = grpc::CreateCustomChannel("127.0.0.1:" + std::to_string(app_->bound_port()), credentials, args);
    auto stub = v1::SessionService::NewStub(channel);
    grpc::ClientContext ctx;
    ctx.set_deadline(std::chrono::system_clock::now() + 5s);
    ctx.set_wait_for_ready(reach == Reach::kMustReachServer);
    if (token) ctx.AddMetadata("authorization", std::string("Bearer ") + token);
    return stub->ListSessions(&ctx, {}, out);
  }
  static std::shared_ptr<grpc::ChannelCredentials> Trusting(const std::string& ca_dir, bool with_client_cert) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = Read(std::filesystem::path(ca_dir) / "ca.pem");
    if (with_client_cert) {
      ssl.pem_cert_chain = Read(std::filesystem::path(ca_dir) / "client.pem");
      ssl.pem_private_key = Read(std::filesystem::path(ca_dir) / "client.key");
    }
    return grpc::SslCredentials(ssl);
  }

  static std::filesystem::path dir_;
  std::unique_ptr<ServerApp> app_;
};
std::filesystem::path TlsTest::dir_;

TEST_F(TlsTest, ATrustingClientGetsThroughAndOthersAreRefused) {
  Start(false);
  v1::ListSessionsResponse r;
  const auto ok = List(Trusting(dir_.string(), false), "instructor-token-tls1", &r);
  ASSERT_TRUE(ok.ok()) << ok.error_message();
  ASSERT_EQ(r.sessions_size(), 1);
  EXPECT_EQ(r.sessions(0).session_id(), "t1");
  // Tokens are still checked over TLS.
  EXPECT_EQ(List(Trusting(dir_.string(), false), nullptr, &r).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  // A client trusting another CA, or speaking plain TCP, never reaches a handler.
  EXPECT_EQ(
      List(Trusting((dir_ / "other").string(), false), "instructor-token-tls1", &r, Reach::kMayBeRefused).error_code(),
      grpc::StatusCode::UNAVAILABLE);
  EXPECT_EQ(List(grpc::InsecureChannelCredentials(), "instructor-token-tls1", &r, Reach::kMayBeRefused).error_code(),
            grpc::StatusCode::UNAVAILABLE);
}

TEST_F(TlsTest, WithClientCertificatesRequiredAClientWithoutOneIsRefused) {
  Start(true);
  v1::ListSessionsResponse r;
  EXPECT_EQ(List(Trusting(dir_.string(), false), "instructor-token-tls1", &r, Reach::kMayBeRefused).error_code(),
            grpc::StatusCode::UNAVAILABLE);
  // A certificate from another CA is no better.
  grpc::SslCredentialsOptions foreign;
  foreign.pem_root_certs = Read(dir_ / "ca.pem");
  foreign.pem_cert_chain = Read(dir_ / "other" / "client.pem");
  foreign.pem_private_key = Read(dir_ / "other" / "client.key");
  EXPECT_EQ(List(grpc::SslCredentials(foreign), "instructor-token-tls1", &r, Reach::kMayBeRefused).error_code(),
            grpc::StatusCode::UNAVAILABLE);
  const auto ok = List(Trusting(dir_.string(), true), "instructor-token-tls1", &r);
  EXPECT_TRUE(ok.ok()) << ok.error_message();
}

TEST(TlsOptions, BadFilesStopTheServerBeforeItStarts) {
  ServerOptions o;
  o.listen_address = "127.0.0.1:0";
  o.tls_cert_file = "/nonexistent/server.pem";
  o.tls_key_file = "/nonexistent/server.key";
  try {
    ServerApp app(o);
    FAIL() << "started without its certificate";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read TLS"), std::string::npos) << e.what();
  }
  o.tls_key_file.clear();
  EXPECT_THROW(ServerApp{o}, std::runtime_error);  // a certificate without its key
}

}  // namespace
}  // namespace hapsim::service
