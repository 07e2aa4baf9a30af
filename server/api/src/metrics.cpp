#include "hapsim/api/metrics.h"

#include <prometheus/client_metric.h>
#include <prometheus/metric_family.h>
#include <prometheus/text_serializer.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <asio/ip/tcp.hpp>
#include <asio/read_until.hpp>
#include <asio/streambuf.hpp>
#include <asio/write.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace hapsim::service {
namespace {

using Labels = std::vector<prometheus::ClientMetric::Label>;

// Families in prometheus-cpp's model, serialised by its TextSerializer
// (escaping, number format and histogram layout are the library's).
class Families {
 public:
  Families& Family(const char* name, prometheus::MetricType type, const char* help) {
    families_.push_back({name, help, type, {}});
    return *this;
  }
  Families& Sample(Labels labels, double value) {
    prometheus::ClientMetric m;
    m.label = std::move(labels);
    if (families_.back().type == prometheus::MetricType::Counter)
      m.counter.value = value;
    else
      m.gauge.value = value;
    families_.back().metric.push_back(std::move(m));
    return *this;
  }
  Families& Histogram(Labels labels, const TickHistogram::Snapshot& h) {
    prometheus::ClientMetric m;
    m.label = std::move(labels);
    std::uint64_t cumulative = 0;
    for (std::size_t b = 0; b < TickHistogram::kBuckets; ++b) {
      cumulative += h.counts[b];
      const double bound = b < TickHistogram::kUpperBounds_s.size() ? TickHistogram::kUpperBounds_s[b]
                                                                    : std::numeric_limits<double>::infinity();
      m.histogram.bucket.push_back({cumulative, bound});
    }
    m.histogram.sample_count = cumulative;
    m.histogram.sample_sum = h.sum_s;
    families_.back().metric.push_back(std::move(m));
    return *this;
  }
  std::string Text() const { return prometheus::TextSerializer().Serialize(families_); }

 private:
  std::vector<prometheus::MetricFamily> families_;
};

constexpr auto kCounter = prometheus::MetricType::Counter;
constexpr auto kGauge = prometheus::MetricType::Gauge;
constexpr auto kHistogram = prometheus::MetricType::Histogram;

// The boot time in unix seconds: /proc/stat's btime, as the Go and Python clients read it.
double ReadBootUnixSeconds() {
  double boot_unix_s = 0.0;
  std::ifstream proc_stat("/proc/stat");
  for (std::string key; proc_stat >> key;) {
    if (key == "btime") {
      proc_stat >> boot_unix_s;
      break;
    }
    proc_stat.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return boot_unix_s;
}

// CPU time, start time and memory from /proc/self/stat (nothing if it cannot be read).
void AddProcStatMetrics(Families& f) {
  const double ticks_per_s = static_cast<double>(::sysconf(_SC_CLK_TCK));
  const double page_bytes = static_cast<double>(::sysconf(_SC_PAGESIZE));
  std::ifstream stat_file("/proc/self/stat");
  std::string stat((std::istreambuf_iterator<char>(stat_file)), std::istreambuf_iterator<char>());
  // Fields after the command name "(...)": state is field 3; utime 14, stime 15, starttime 22, vsize 23, rss 24.
  const auto close = stat.rfind(')');
  if (close == std::string::npos) return;
  std::istringstream in(stat.substr(close + 2));
  std::vector<std::string> field(3, "");  // field[k] is field k (1-based); 1 and 2 come before the state
  for (std::string word; in >> word;) field.push_back(word);
  auto number = [&](std::size_t k) { return k < field.size() ? std::strtod(field[k].c_str(), nullptr) : 0.0; };
  const double boot_unix_s = ReadBootUnixSeconds();
  f.Family("process_cpu_seconds_total", kCounter, "Total user and system CPU time spent in seconds.")
      .Sample({}, (number(14) + number(15)) / ticks_per_s);
  f.Family("process_start_time_seconds", kGauge, "Start time of the process since unix epoch in seconds.")
      .Sample({}, boot_unix_s + number(22) / ticks_per_s);
  f.Family("process_virtual_memory_bytes", kGauge, "Virtual memory size in bytes.").Sample({}, number(23));
  f.Family("process_resident_memory_bytes", kGauge, "Resident memory size in bytes.")
      .Sample({}, number(24) * page_bytes);
}

std::size_t CountOpenFds() {
  std::size_t fds = 0;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    ++fds;
  }
  return fds;
}

// The standard process metrics (as the Go and Python clients name them),
// read from /proc/self at scrape time.
void AddProcessMetrics(Families& f) {
  AddProcStatMetrics(f);
  f.Family("process_open_fds", kGauge, "Number of open file descriptors.")
      .Sample({}, static_cast<double>(CountOpenFds()));
  rlimit limit{};
  if (::getrlimit(RLIMIT_NOFILE, &limit) == 0) {
    f.Family("process_max_fds", kGauge, "Maximum number of open file descriptors.")
        .Sample({}, static_cast<double>(limit.rlim_cur));
  }
}

// The server's totals: sessions, the DDS thread's pose routing, the tick pool.
void AddServerMetrics(Families& w, std::size_t sessions, const ServerDdsCounters& dds, const TickPoolStats& pool) {
  w.Family("hapsim_sessions", kGauge, "Sessions open on this server.").Sample({}, static_cast<double>(sessions));
  w.Family("hapsim_poses_accepted_total", kCounter, "Device poses accepted by any session.")
      .Sample({}, static_cast<double>(dds.poses_accepted.load()));
  w.Family("hapsim_poses_dropped_total", kCounter, "Device poses dropped before a session used them, by reason.")
      .Sample({{"reason", "malformed"}}, static_cast<double>(dds.poses_rejected.load()))
      .Sample({{"reason", "wrong_session"}}, static_cast<double>(dds.poses_wrong_session.load()))
      .Sample({{"reason", "other_device"}}, static_cast<double>(dds.poses_other_device.load()))
      .Sample({{"reason", "stale"}}, static_cast<double>(dds.poses_stale.load()));
  w.Family("hapsim_force_models_written_total", kCounter, "Local force models written to DDS.")
      .Sample({}, static_cast<double>(dds.force_models_written.load()));
  w.Family("hapsim_dds_foreign_model_writers", kGauge,
           "Force-model writers of another participant (another server) in this server's session partitions, "
           "one per writer and session. Should be 0: give each server its own DDS domain.")
      .Sample({}, static_cast<double>(dds.foreign_model_writers.load()));
  w.Family("hapsim_tick_pool_ticks_total", kCounter, "Session ticks run by the tick pool.")
      .Sample({}, static_cast<double>(pool.ticks));
  w.Family("hapsim_tick_pool_wakeups_total", kCounter, "Tick pool worker wake-ups.")
      .Sample({}, static_cast<double>(pool.wakeups));
}

void AddAuthMetrics(Families& w, const AuthCounters& auth) {
  w.Family("hapsim_auth_failures_total", kCounter,
           "Calls refused by the class config: no or unknown token, or a role/session the token may not touch.")
      .Sample({{"reason", "unauthenticated"}}, static_cast<double>(auth.unauthenticated.load()))
      .Sample({{"reason", "permission_denied"}}, static_cast<double>(auth.permission_denied.load()));
}

void AddGrpcCallMetrics(Families& w, const GrpcCallCounter& calls) {
  w.Family("hapsim_grpc_calls_total", kCounter, "gRPC calls answered, by method and status code.");
  for (const auto& [method, counts] : calls.Snapshot()) {
    for (int code = 0; code < GrpcCallCounter::kCodes; ++code) {
      if (counts[static_cast<std::size_t>(code)] == 0) continue;
      w.Sample({{"method", method}, {"code", GrpcCodeName(code)}},
               static_cast<double>(counts[static_cast<std::size_t>(code)]));
    }
  }
}

// Per session: one family at a time, a sample per session.
struct PerSessionMetric {
  const char* name;
  prometheus::MetricType type;
  const char* help;
  double (*get)(const Session&);
};
const PerSessionMetric kPerSessionMetrics[] = {
    {"hapsim_session_ticks_total", kCounter, "Ticks the session ran.",
     [](const Session& s) { return static_cast<double>(s.counters().tick.ticks.load()); }},
    {"hapsim_session_tick_seconds_total", kCounter,
     "Wall time spent in the session's ticks up to the scene stepped (divide by ticks for the mean tick time).",
     [](const Session& s) { return static_cast<double>(s.counters().tick.tick_work_ns.load()) * 1e-9; }},
    {"hapsim_session_late_ticks_total", kCounter, "Ticks that started more than one period after they were due.",
     [](const Session& s) { return static_cast<double>(s.counters().tick.late_ticks.load()); }},
    {"hapsim_session_max_tick_lateness_seconds", kGauge, "Worst start delay of a tick after it was due.",
     [](const Session& s) { return static_cast<double>(s.counters().tick.max_lateness_ns.load()) * 1e-9; }},
    {"hapsim_session_sim_time_seconds", kGauge, "Simulated time of the session.",
     [](const Session& s) { return s.counters().tick.sim_time_s.load(); }},
    {"hapsim_session_viewers", kGauge, "Open Subscribe streams.",
     [](const Session& s) { return static_cast<double>(s.counters().viewers.connected.load()); }},
    {"hapsim_session_viewer_frames_sent_total", kCounter, "Frames written to the session's viewers.",
     [](const Session& s) { return static_cast<double>(s.counters().viewers.frames_sent.load()); }},
    {"hapsim_session_viewer_bytes_sent_total", kCounter, "Encoded bytes of those frames.",
     [](const Session& s) { return static_cast<double>(s.counters().viewers.bytes_sent.load()); }},
    {"hapsim_session_viewer_frames_coalesced_total", kCounter,
     "Snapshots a slow viewer never got (replaced by newer ones).",
     [](const Session& s) { return static_cast<double>(s.counters().viewers.frames_coalesced.load()); }},
    {"hapsim_session_poses_received_total", kCounter, "Poses the session accepted from its device.",
     [](const Session& s) { return static_cast<double>(s.counters().poses.received.load()); }},
    {"hapsim_session_poses_rejected_total", kCounter, "Malformed poses dropped (NaN, out of range).",
     [](const Session& s) { return static_cast<double>(s.counters().poses.rejected.load()); }},
    {"hapsim_session_poses_stale_total", kCounter, "Owner's poses dropped as stale (seq not rising).",
     [](const Session& s) { return static_cast<double>(s.counters().poses.stale.load()); }},
    {"hapsim_session_poses_other_device_total", kCounter, "Poses dropped because another device owns the session.",
     [](const Session& s) { return static_cast<double>(s.counters().poses.from_other_devices.load()); }},
    {"hapsim_session_force_models_sent_total", kCounter, "Local force models sent to the session's device.",
     [](const Session& s) { return static_cast<double>(s.counters().tick.force_models_sent.load()); }},
    {"hapsim_session_force_models_held_total", kCounter,
     "Force models not sent: the device would not feel the change (--model-deadband).",
     [](const Session& s) { return static_cast<double>(s.counters().tick.force_models_held.load()); }},
    {"hapsim_session_poses_unused_total", kCounter,
     "Poses of the owning device's sequence no tick used (lost, overwritten, superseded, or not sent).",
     [](const Session& s) { return static_cast<double>(s.counters().tick.poses_unused.load()); }},
    {"hapsim_session_numerical_resets_total", kCounter, "Physics blow-ups detected and recovered.",
     [](const Session& s) { return static_cast<double>(s.counters().tick.numerical_resets.load()); }},
    {"hapsim_session_device_streaming", kGauge, "1 while a pose arrived within the pose timeout.",
     [](const Session& s) { return s.counters().tick.device_streaming.load() ? 1.0 : 0.0; }},
    {"hapsim_session_peak_tool_force_newtons", kGauge, "Largest tool force since creation or reset.",
     [](const Session& s) { return s.counters().tick.peak_tool_force_N.load(); }},
};

// Distributions the tick records without a lock (tick_histogram.h).
struct PerSessionHistogram {
  const char* name;
  const char* help;
  const TickHistogram& (*get)(const Session&);
};
const PerSessionHistogram kPerSessionHistograms[] = {
    {"hapsim_session_tick_work_seconds", "Wall time of a tick up to the scene stepped.",
     [](const Session& s) -> const TickHistogram& { return s.counters().tick.tick_work; }},
    {"hapsim_session_tick_lateness_seconds", "How long after it was due a tick started.",
     [](const Session& s) -> const TickHistogram& { return s.counters().tick.tick_lateness; }},
    {"hapsim_session_pose_to_model_seconds",
     "From a fresh pose's arrival to the force model of the tick it clocked stamped for DDS (t_server_ns, just "
     "before the write): the server's share "
     "of the device's round trip.",
     [](const Session& s) -> const TickHistogram& { return s.counters().tick.pose_to_model; }},
};

Labels SessionLabels(const Session& s) { return Labels{{"session", s.id()}, {"scene", s.config().scene}}; }

void AddPerSessionMetrics(Families& w, const std::vector<std::shared_ptr<Session>>& sessions) {
  for (const auto& m : kPerSessionMetrics) {
    w.Family(m.name, m.type, m.help);
    for (const auto& s : sessions) w.Sample(SessionLabels(*s), m.get(*s));
  }
  for (const auto& h : kPerSessionHistograms) {
    w.Family(h.name, kHistogram, h.help);
    for (const auto& s : sessions) w.Histogram(SessionLabels(*s), h.get(*s).Read());
  }
}

}  // namespace

std::string FormatMetrics(const SessionRegistry& registry, const ServerDdsCounters& dds, const TickPoolStats& pool,
                          const GrpcCallCounter* calls, const AuthCounters* auth) {
  const auto sessions = registry.List();
  Families w;
  AddServerMetrics(w, sessions.size(), dds, pool);
  if (auth) AddAuthMetrics(w, *auth);
  if (calls) AddGrpcCallMetrics(w, *calls);
  AddPerSessionMetrics(w, sessions);
  AddProcessMetrics(w);
  return w.Text();
}

struct MetricsEndpoint::Impl {
  asio::io_context io;
  asio::ip::tcp::acceptor acceptor{io};
};

MetricsEndpoint::MetricsEndpoint(const std::string& listen_address, std::function<std::string()> render)
    : impl_(std::make_unique<Impl>()), render_(std::move(render)) {
  const auto colon = listen_address.rfind(':');
  if (colon == std::string::npos) throw std::runtime_error("metrics: address must be host:port, got '" + listen_address + "'");
  asio::error_code ec;
  const auto address = asio::ip::make_address(listen_address.substr(0, colon), ec);
  int port = -1;
  try {
    port = std::stoi(listen_address.substr(colon + 1));
  } catch (const std::exception&) {
  }
  if (ec || port < 0 || port > 65535) throw std::runtime_error("metrics: bad address '" + listen_address + "'");
  const asio::ip::tcp::endpoint endpoint(address, static_cast<unsigned short>(port));
  impl_->acceptor.open(endpoint.protocol(), ec);
  if (!ec) impl_->acceptor.set_option(asio::ip::tcp::acceptor::reuse_address(true), ec);
  if (!ec) impl_->acceptor.bind(endpoint, ec);
  if (!ec) impl_->acceptor.listen(16, ec);
  if (ec) throw std::runtime_error("metrics: cannot listen on " + listen_address + ": " + ec.message());
  bound_port_ = impl_->acceptor.local_endpoint().port();
  thread_ = std::thread([this] { Serve(); });
}

MetricsEndpoint::~MetricsEndpoint() {
  stop_ = true;
  asio::error_code ec;
  impl_->acceptor.cancel(ec);
  // A blocking accept is woken by a connection of our own.
  asio::ip::address address = impl_->acceptor.local_endpoint(ec).address();
  if (ec || address.is_unspecified()) address = asio::ip::make_address("127.0.0.1");
  asio::ip::tcp::socket poke(impl_->io);
  poke.connect({address, static_cast<unsigned short>(bound_port_)}, ec);
  if (thread_.joinable()) thread_.join();
}

void MetricsEndpoint::Serve() {
  while (!stop_) {
    asio::ip::tcp::socket socket(impl_->io);
    asio::error_code ec;
    impl_->acceptor.accept(socket, ec);
    if (stop_) return;
    if (ec) continue;
    const timeval timeout{2, 0};
    ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    asio::streambuf request(8192);
    asio::read_until(socket, request, "\r\n\r\n", ec);
    ++requests_;
    std::string status = "400 Bad Request", body = "bad request\n", type = "text/plain";
    if (!ec) {
      std::istream in(&request);
      std::string method, path;
      in >> method >> path;
      if (method == "GET" && (path == "/metrics" || path.rfind("/metrics?", 0) == 0)) {
        status = "200 OK";
        body = render_();
        type = "text/plain; version=0.0.4; charset=utf-8";
      } else {
        status = "404 Not Found";
        body = "only GET /metrics is served\n";
      }
    }
    const std::string response = "HTTP/1.1 " + status + "\r\nContent-Type: " + type +
                                 "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" + body;
    asio::write(socket, asio::buffer(response), ec);
    // Lingering close: closing with unread request bytes (an oversized or
    // garbage request) would send a reset that can destroy the response in
    // the client's buffer. Stop sending, then drain what the client still
    // sends, bounded by 64 KiB and the 2 s receive timeout.
    socket.shutdown(asio::ip::tcp::socket::shutdown_send, ec);
    char sink[4096];
    for (std::size_t drained = 0; !ec && drained < 65536;) drained += socket.read_some(asio::buffer(sink), ec);
  }
}

}  // namespace hapsim::service
