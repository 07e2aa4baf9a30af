// GET /metrics: Prometheus text that a scraper can parse, whose numbers are
// the server's own counters, and an endpoint that answers garbage with a
// status and keeps serving.
#include "hapsim/api/metrics.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <asio/connect.hpp>
#include <asio/ip/tcp.hpp>
#include <asio/read.hpp>
#include <asio/write.hpp>
#include <chrono>
#include <cstring>
#include <ctime>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "hapsim/app/server_app.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "test_dds_domain.h"

namespace hapsim::service {
namespace {

using namespace std::chrono_literals;

// Sends `request` raw and returns the whole response (the server closes).
std::string Http(int port, const std::string& request, bool half_close = false) {
  asio::io_context io;
  asio::ip::tcp::socket socket(io);
  socket.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  asio::error_code ec;
  // The server may answer (and stop reading) before a long request is all
  // written: write errors are expected then, the response still arrives.
  asio::write(socket, asio::buffer(request), ec);
  if (half_close) socket.shutdown(asio::ip::tcp::socket::shutdown_send, ec);
  std::string response;
  char buffer[4096];
  for (;;) {
    const std::size_t n = socket.read_some(asio::buffer(buffer), ec);
    response.append(buffer, n);
    if (ec) break;
  }
  return response;
}

// Wall time [s] when this test binary was loaded: its process had just started.
const double kTestBinaryLoaded_s = static_cast<double>(std::time(nullptr));

std::string Body(const std::string& response) { return response.substr(response.find("\r\n\r\n") + 4); }

class MetricsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ServerOptions o;
    o.listen_address = "127.0.0.1:0";
    o.metrics_listen_address = "127.0.0.1:0";
    o.dds.domain_id = test::ClaimTestDdsDomain();
    app_ = std::make_unique<ServerApp>(o);
    ASSERT_GT(app_->metrics_port(), 0);
  }
  void TearDown() override { app_->Shutdown(); }
  std::unique_ptr<ServerApp> app_;
};

TEST_F(MetricsTest, TheExpositionParsesAndCarriesTheSessionCounters) {
  const auto m1 = app_->registry().Create("m1", "tissue_block", "test", {});
  app_->registry().Create("m2", "acupuncture", "test", {});
  // Wait for ticks rather than for a time: under sanitizers a tick is slower.
  for (int k = 0; k < 1000 && m1->counters().tick.ticks.load() < 50; ++k) std::this_thread::sleep_for(10ms);
  const std::string response = Http(app_->metrics_port(), "GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n");
  ASSERT_EQ(response.rfind("HTTP/1.1 200 OK\r\n", 0), 0u) << response.substr(0, 200);
  EXPECT_NE(response.find("Content-Type: text/plain; version=0.0.4"), std::string::npos);

  // Every line is a HELP, a TYPE or a sample `name{labels} value`; every
  // sample's family was declared with HELP and TYPE first (a histogram's
  // samples are its name + _bucket, _sum, _count).
  const std::regex sample(R"(^([a-z_]+)(\{[a-z_]+="[^"]*"(,[a-z_]+="[^"]*")*\})? (-?[0-9.]+(e[-+]?[0-9]+)?)$)");
  std::map<std::string, int> declared;
  std::set<std::string> histograms;
  std::map<std::string, double> values;
  std::istringstream lines(Body(response));
  std::string line;
  int samples = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("# HELP ", 0) == 0 || line.rfind("# TYPE ", 0) == 0) {
      const std::string family = line.substr(7, line.find(' ', 7) - 7);
      ++declared[family];
      if (line.rfind("# TYPE ", 0) == 0 && line.substr(line.rfind(' ') + 1) == "histogram") histograms.insert(family);
      continue;
    }
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, sample)) << "not Prometheus text: " << line;
    std::string family = m[1];
    for (const char* suffix : {"_bucket", "_sum", "_count"}) {
      const std::string base = family.substr(0, family.size() - std::min(family.size(), std::strlen(suffix)));
      if (family.size() > base.size() && family.substr(base.size()) == suffix && histograms.count(base)) family = base;
    }
    EXPECT_EQ(declared[family], 2) << m[1] << " has no HELP/TYPE";
    values[line.substr(0, line.rfind(' '))] = std::stod(m[4]);
    ++samples;
  }
  EXPECT_GT(samples, 30);
  EXPECT_EQ(values["hapsim_sessions"], 2.0);
  // The numbers are the sessions' own: ticks grew between scrape and now, never past.
  const double ticks = values["hapsim_session_ticks_total{session=\"m1\",scene=\"tissue_block\"}"];
  EXPECT_GE(ticks, 50.0);  // waited for at least that many
  EXPECT_LE(ticks, static_cast<double>(m1->counters().tick.ticks.load()));
  EXPECT_EQ(values.count("hapsim_session_ticks_total{session=\"m2\",scene=\"acupuncture\"}"), 1u);
  // Mean tick time from the two counters, as a dashboard would compute it.
  const double work_s = values["hapsim_session_tick_seconds_total{session=\"m1\",scene=\"tissue_block\"}"];
  const double m1_ticks = values["hapsim_session_ticks_total{session=\"m1\",scene=\"tissue_block\"}"];
  EXPECT_GT(work_s / m1_ticks, 0.0);
  EXPECT_LT(work_s / m1_ticks, 0.1);  // tens of µs in release; bounded loosely for sanitizer builds

  // The tick's distributions: cumulative buckets ending at +Inf = count,
  // the count within the ticks run, the sum the same wall time as the counter's.
  const std::string m1_labels = "session=\"m1\",scene=\"tissue_block\"";
  for (const char* h : {"hapsim_session_tick_work_seconds", "hapsim_session_tick_lateness_seconds"}) {
    EXPECT_EQ(histograms.count(h), 1u) << h;
    const double count = values[std::string(h) + "_count{" + m1_labels + "}"];
    EXPECT_GE(count, 50.0) << h;
    EXPECT_LE(count, static_cast<double>(m1->counters().tick.ticks.load())) << h;
    EXPECT_EQ(values[std::string(h) + "_bucket{" + m1_labels + ",le=\"+Inf\"}"], count) << h;
    double previous = 0.0;
    for (const double le : TickHistogram::kUpperBounds_s) {
      std::ostringstream key;
      key << h << "_bucket{" << m1_labels << ",le=\"" << le << "\"}";
      ASSERT_EQ(values.count(key.str()), 1u) << key.str();
      EXPECT_GE(values[key.str()], previous) << key.str();
      previous = values[key.str()];
    }
  }
  // The histogram is written after the counters in one scrape and records
  // the same ticks: between the counters' reading and the session's now
  // (give or take the one tick that may be between its two records).
  const double hist_count = values["hapsim_session_tick_work_seconds_count{" + m1_labels + "}"];
  const double hist_sum_s = values["hapsim_session_tick_work_seconds_sum{" + m1_labels + "}"];
  EXPECT_GE(hist_count, m1_ticks - 1.0);
  EXPECT_LE(hist_count, static_cast<double>(m1->counters().tick.ticks.load()) + 1.0);
  EXPECT_GE(hist_sum_s, 0.0);
  EXPECT_LE(hist_sum_s, static_cast<double>(m1->counters().tick.tick_work_ns.load()) * 1e-9 + 1e-9);  // recorded after
  // The standard process metrics, read from /proc.
  EXPECT_GT(values["process_resident_memory_bytes"], 1e6);
  EXPECT_GE(values["process_virtual_memory_bytes"], values["process_resident_memory_bytes"]);
  EXPECT_GE(values["process_open_fds"], 3.0);
  EXPECT_GE(values["process_max_fds"], values["process_open_fds"]);
  EXPECT_GE(values["process_cpu_seconds_total"], 0.0);
  // The process started just before this file's statics were initialised,
  // however long the test then took (building a vessel takes a minute under
  // ASan); btime and the start tick are whole seconds and clock ticks.
  EXPECT_LE(values["process_start_time_seconds"], kTestBinaryLoaded_s + 1.0);
  EXPECT_GE(values["process_start_time_seconds"], kTestBinaryLoaded_s - 5.0);
}

TEST_F(MetricsTest, GrpcCallsAreCountedByMethodAndCode) {
  auto channel =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(app_->bound_port()), grpc::InsecureChannelCredentials());
  auto stub = hapsim::v1::SessionService::NewStub(channel);
  for (int k = 0; k < 3; ++k) {  // three unknown sessions: NOT_FOUND
    grpc::ClientContext ctx;
    hapsim::v1::SessionRef req;
    req.set_session_id("ghost");
    hapsim::v1::SessionInfo info;
    stub->GetSession(&ctx, req, &info);
  }
  {
    grpc::ClientContext ctx;
    hapsim::v1::ListSessionsRequest req;
    hapsim::v1::ListSessionsResponse list;
    EXPECT_TRUE(stub->ListSessions(&ctx, req, &list).ok());
  }
  const std::string body = Body(Http(app_->metrics_port(), "GET /metrics HTTP/1.1\r\n\r\n"));
  EXPECT_NE(body.find("hapsim_grpc_calls_total{method=\"/hapsim.v1.SessionService/GetSession\",code=\"NOT_FOUND\"} 3"),
            std::string::npos)
      << body.substr(body.find("hapsim_grpc_calls_total"), 400);
  EXPECT_NE(body.find("hapsim_grpc_calls_total{method=\"/hapsim.v1.SessionService/ListSessions\",code=\"OK\"} 1"),
            std::string::npos);
}

TEST_F(MetricsTest, GarbageGetsAStatusAndTheEndpointKeepsServing) {
  EXPECT_EQ(Http(app_->metrics_port(), "GET /other HTTP/1.1\r\n\r\n").rfind("HTTP/1.1 404", 0), 0u);
  EXPECT_EQ(Http(app_->metrics_port(), "\x01\x02 garbage without an end", /*half_close=*/true).rfind("HTTP/1.1 400", 0),
            0u);
  EXPECT_EQ(Http(app_->metrics_port(), std::string(20000, 'A'), true).rfind("HTTP/1.1 400", 0), 0u);  // over 8 KiB
  EXPECT_EQ(Http(app_->metrics_port(), "GET /metrics HTTP/1.1\r\n\r\n").rfind("HTTP/1.1 200", 0), 0u);
}

TEST(Metrics, AnUnusableAddressIsAClearError) {
  EXPECT_THROW(MetricsEndpoint("nonsense", [] { return std::string(); }), std::runtime_error);
  EXPECT_THROW(MetricsEndpoint("127.0.0.1:99999", [] { return std::string(); }), std::runtime_error);
}

}  // namespace
}  // namespace hapsim::service
