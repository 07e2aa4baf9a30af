#include "hapsim/service/metrics.h"

#include <sstream>
#include <stdexcept>

#include <asio/ip/tcp.hpp>
#include <asio/read_until.hpp>
#include <asio/streambuf.hpp>
#include <asio/write.hpp>
#include <sys/socket.h>
#include <sys/time.h>

namespace hapsim::service {
namespace {

// Prometheus label values escape \, " and newline.
std::string Label(const std::string& v) {
  std::string out;
  for (const char c : v) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

class Writer {
 public:
  // One metric family: HELP, TYPE, then samples.
  Writer& Family(const char* name, const char* type, const char* help) {
    out_ << "# HELP " << name << ' ' << help << "\n# TYPE " << name << ' ' << type << '\n';
    name_ = name;
    return *this;
  }
  template <class T>
  Writer& Sample(const std::string& labels, T value) {
    out_ << name_ << labels << ' ' << value << '\n';
    return *this;
  }
  std::string Text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::string name_;
};

}  // namespace

std::string FormatMetrics(const SessionRegistry& registry, const ServerDdsCounters& dds, const TickPoolStats& pool,
                          const GrpcCallCounter* calls, const AuthCounters* auth) {
  const auto sessions = registry.List();
  Writer w;
  w.Family("hapsim_sessions", "gauge", "Sessions open on this server.").Sample("", sessions.size());
  w.Family("hapsim_poses_accepted_total", "counter", "Device poses accepted by any session.")
      .Sample("", dds.poses_accepted.load());
  w.Family("hapsim_poses_dropped_total", "counter", "Device poses dropped before a session used them, by reason.")
      .Sample("{reason=\"malformed\"}", dds.poses_rejected.load())
      .Sample("{reason=\"wrong_session\"}", dds.poses_wrong_session.load())
      .Sample("{reason=\"other_device\"}", dds.poses_other_device.load())
      .Sample("{reason=\"stale\"}", dds.poses_stale.load());
  w.Family("hapsim_force_models_written_total", "counter", "Local force models written to DDS.")
      .Sample("", dds.force_models_written.load());
  w.Family("hapsim_dds_foreign_model_writers", "gauge",
           "Force-model writers of another participant (another server) in this server's session partitions, "
           "one per writer and session. Should be 0: give each server its own DDS domain.")
      .Sample("", dds.foreign_model_writers.load());
  w.Family("hapsim_tick_pool_ticks_total", "counter", "Session ticks run by the tick pool.").Sample("", pool.ticks);
  w.Family("hapsim_tick_pool_wakeups_total", "counter", "Tick pool worker wake-ups.").Sample("", pool.wakeups);
  if (auth) {
    w.Family("hapsim_auth_failures_total", "counter",
             "Calls refused by the class config: no or unknown token, or a role/session the token may not touch.")
        .Sample("{reason=\"unauthenticated\"}", auth->unauthenticated.load())
        .Sample("{reason=\"permission_denied\"}", auth->permission_denied.load());
  }
  if (calls) {
    w.Family("hapsim_grpc_calls_total", "counter", "gRPC calls answered, by method and status code.");
    for (const auto& [method, counts] : calls->Snapshot()) {
      for (int code = 0; code < GrpcCallCounter::kCodes; ++code) {
        if (counts[static_cast<std::size_t>(code)] == 0) continue;
        w.Sample("{method=\"" + Label(method) + "\",code=\"" + GrpcCodeName(code) + "\"}",
                 counts[static_cast<std::size_t>(code)]);
      }
    }
  }

  // Per session: one family at a time, a sample per session.
  struct PerSession {
    const char* name;
    const char* type;
    const char* help;
    double (*get)(const Session&);
  };
  static const PerSession kPerSession[] = {
      {"hapsim_session_ticks_total", "counter", "Ticks the session ran.",
       [](const Session& s) { return static_cast<double>(s.counters().ticks.load()); }},
      {"hapsim_session_tick_seconds_total", "counter",
       "Wall time spent in the session's ticks up to the scene stepped (divide by ticks for the mean tick time).",
       [](const Session& s) { return static_cast<double>(s.counters().tick_work_ns.load()) * 1e-9; }},
      {"hapsim_session_late_ticks_total", "counter", "Ticks that started more than one period after they were due.",
       [](const Session& s) { return static_cast<double>(s.counters().late_ticks.load()); }},
      {"hapsim_session_max_tick_lateness_seconds", "gauge", "Worst start delay of a tick after it was due.",
       [](const Session& s) { return static_cast<double>(s.counters().max_lateness_ns.load()) * 1e-9; }},
      {"hapsim_session_sim_time_seconds", "gauge", "Simulated time of the session.",
       [](const Session& s) { return s.counters().sim_time_s.load(); }},
      {"hapsim_session_viewers", "gauge", "Open Subscribe streams.",
       [](const Session& s) { return static_cast<double>(s.counters().viewers.load()); }},
      {"hapsim_session_viewer_frames_sent_total", "counter", "Frames written to the session's viewers.",
       [](const Session& s) { return static_cast<double>(s.counters().viewer_frames_sent.load()); }},
      {"hapsim_session_viewer_bytes_sent_total", "counter", "Encoded bytes of those frames.",
       [](const Session& s) { return static_cast<double>(s.counters().viewer_bytes_sent.load()); }},
      {"hapsim_session_viewer_frames_coalesced_total", "counter",
       "Snapshots a slow viewer never got (replaced by newer ones).",
       [](const Session& s) { return static_cast<double>(s.counters().viewer_frames_coalesced.load()); }},
      {"hapsim_session_poses_received_total", "counter", "Poses the session accepted from its device.",
       [](const Session& s) { return static_cast<double>(s.counters().poses_received.load()); }},
      {"hapsim_session_poses_rejected_total", "counter", "Malformed poses dropped (NaN, out of range).",
       [](const Session& s) { return static_cast<double>(s.counters().poses_rejected.load()); }},
      {"hapsim_session_poses_stale_total", "counter", "Owner's poses dropped as stale (seq not rising).",
       [](const Session& s) { return static_cast<double>(s.counters().poses_stale.load()); }},
      {"hapsim_session_poses_other_device_total", "counter", "Poses dropped because another device owns the session.",
       [](const Session& s) { return static_cast<double>(s.counters().poses_from_other_devices.load()); }},
      {"hapsim_session_force_models_sent_total", "counter", "Local force models sent to the session's device.",
       [](const Session& s) { return static_cast<double>(s.counters().force_models_sent.load()); }},
      {"hapsim_session_numerical_resets_total", "counter", "Physics blow-ups detected and recovered.",
       [](const Session& s) { return static_cast<double>(s.counters().numerical_resets.load()); }},
      {"hapsim_session_device_streaming", "gauge", "1 while a pose arrived within the pose timeout.",
       [](const Session& s) { return s.counters().device_streaming.load() ? 1.0 : 0.0; }},
      {"hapsim_session_peak_tool_force_newtons", "gauge", "Largest tool force since creation or reset.",
       [](const Session& s) { return s.counters().peak_tool_force_N.load(); }},
  };
  for (const auto& m : kPerSession) {
    w.Family(m.name, m.type, m.help);
    for (const auto& s : sessions) {
      w.Sample("{session=\"" + Label(s->id()) + "\",scene=\"" + Label(s->config().scene) + "\"}", m.get(*s));
    }
  }
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
