// Prometheus text exposition (format 0.0.4) of the server's counters,
// distributions and the standard process metrics — built in prometheus-cpp's
// metric model and written by its TextSerializer (Debian's prometheus-cpp-dev)
// — and a minimal HTTP endpoint serving it at GET /metrics (on Asio: small,
// bounded against slow clients, no extra web server). The tick records its
// histograms lock-free (tick_histogram.h); they become prometheus-cpp
// histograms at scrape time. Every metric is documented in docs/metrics.md.
// Not exported: device round trips (the bridges measure them; the server's
// share is hapsim_session_pose_to_model_seconds).
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "hapsim/api/grpc_call_counter.h"
#include "hapsim/classroom/access_policy.h"
#include "hapsim/device_link/server_dds.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/runtime/tick_pool.h"

namespace hapsim::service {

// The exposition text for these sessions and server counters.
// `calls` may be null (no gRPC counts), `auth` too (no auth failures).
std::string FormatMetrics(const SessionRegistry& registry, const ServerDdsCounters& dds, const TickPoolStats& pool,
                          const GrpcCallCounter* calls = nullptr, const AuthCounters* auth = nullptr);

// Serves GET /metrics on a TCP address (host:port, port 0: any) from one
// thread of its own. A request is read up to 8 KiB with a 2 s receive
// timeout, so a slow or hostile client delays other scrapes by at most that
// and never the physics; anything but GET /metrics gets 404, a request
// without its header end 400.
class MetricsEndpoint {
 public:
  // Throws std::runtime_error if the address cannot be bound.
  MetricsEndpoint(const std::string& listen_address, std::function<std::string()> render);
  ~MetricsEndpoint();
  int bound_port() const { return bound_port_; }
  std::uint64_t requests() const { return requests_.load(); }

 private:
  void Serve();
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::function<std::string()> render_;
  int bound_port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> requests_{0};
  std::thread thread_;
};

}  // namespace hapsim::service
