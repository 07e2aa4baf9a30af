// The physics server process, assembled: DDS adapter, session registry,
// frame pump, gRPC services. main.cpp parses flags and handles signals.
#pragma once
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/api/metrics.h"
#include "hapsim/api/peer_locator.h"
#include "hapsim/api/session_service.h"
#include "hapsim/api/viewer_service.h"
#include "hapsim/app/persistence.h"
#include "hapsim/classroom/access_policy.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/classroom/server_directory.h"
#include "hapsim/classroom/session_trials.h"
#include "hapsim/dds/dds.h"
#include "hapsim/device_link/server_dds.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/runtime/tick_pool.h"
#include "hapsim/streaming/frame_pump.h"
#include "hapsim/streaming/viewer_hub.h"
#include "hapsim/web/web_console.h"

namespace hapsim::service {

// The site's servers, for SessionService.Locate (docs/deploy.md, "Several servers").
struct DirectoryOptions {
  ServerDirectory directory;
  std::string server_name;                       // this server's name in it
  std::string peer_tls_ca_file;                  // dial the other servers over TLS trusting this PEM CA ("": plain TCP)
  std::chrono::milliseconds peer_timeout{1000};  // a server that has not answered by then is unreachable
};

struct ServerOptions {
  std::string listen_address = "127.0.0.1:50051";
  SessionDefaults sessions;
  int workers = 0;  // tick pool threads; 0: the CPUs this process may use
  // SCHED_FIFO priority of the tick workers (the receive threads one above);
  // 0: normal scheduling. Refused (no CAP_SYS_NICE / RLIMIT_RTPRIO): a warning.
  int rt_priority = 0;
  // CPUs of the 1 kHz path: the tick workers and the pose receive threads run
  // only there, every other thread only on the process's other CPUs (and the
  // tick pool defaults to one worker per tick CPU). Empty: no pinning.
  std::vector<int> tick_cpus;
  // How an idle tick worker waits: asleep, or spinning so its CPU never
  // idles (common/idle_wait.h; for CPUs given to the 1 kHz path).
  common::IdleWait tick_wait = common::IdleWait::kSleep;
  // The DDS thread that routes poses to their sessions: kBatch (default) lets
  // Cyclone's receive thread finish before it runs, kNormal preempts it
  // (two more context switches per wake; kept to measure the difference).
  // With rt_priority both become SCHED_FIFO.
  hapsim::dds::IoThread::Scheduling dds_io_scheduling = hapsim::dds::IoThread::Scheduling::kBatch;
  double quantum_m = 1e-5;  // viewer position quantisation (10 µm)
  int max_message_bytes = 1 << 20;  // larger requests are refused (RESOURCE_EXHAUSTED)
  hapsim::dds::Options dds;
  PoseLimits pose_limits;
  std::string metrics_listen_address;  // host:port for GET /metrics (Prometheus); empty: off
  // The browser console (HTTPS with the TLS files below, else plain HTTP):
  // host:port, empty: off; and the directory of the built web app it serves.
  std::string web_listen_address;
  std::string web_root;
  // Classes, their sessions (created at start) and tokens; none: development
  // mode (no tokens, anyone who reaches the port may do anything).
  std::optional<ClassConfig> classes;
  // TLS: PEM files. Both cert and key, or neither (plain TCP). With
  // client_ca_file, clients must present a certificate signed by that CA.
  std::string tls_cert_file, tls_key_file, tls_client_ca_file;
  // The data directory: trials, scores, recordings and the live sessions
  // kept and brought back at start (persistence.h). None: nothing outlives
  // the process.
  std::optional<PersistenceOptions> persistence;
  // The other servers of the site; none: Locate answers for this server only.
  std::optional<DirectoryOptions> directory;
};

// True for addresses only this machine reaches (127.x, ::1, localhost).
bool IsLoopbackAddress(const std::string& listen_address);

class ServerApp {
 public:
  // Throws on a port/DDS/TLS-file failure or a class session that cannot be created.
  explicit ServerApp(const ServerOptions& options);
  ~ServerApp();

  SessionRegistry& registry() { return *registry_; }
  const ViewerHub& viewers() const { return viewers_; }
  const ServerDds& dds() const { return *dds_; }
  const TickPool& pool() const { return *pool_; }
  const AccessPolicy& policy() const { return policy_; }
  const TrialBook& trials() const { return trials_; }
  Persistence* persistence() { return persistence_.get(); }  // nullptr: no data directory
  int bound_port() const { return bound_port_; }
  int metrics_port() const { return metrics_ ? metrics_->bound_port() : 0; }  // 0: no metrics endpoint
  int web_port() const { return web_ ? web_->bound_port() : 0; }              // 0: no web console
  // Ends viewer streams, stops gRPC, sessions and DDS. Idempotent.
  void Shutdown();

 private:
  // The constructor's steps, in order: make the parts (DDS, pool, registry,
  // pump, services), listen for gRPC, serve /metrics, and create the class
  // config's sessions once everything runs.
  void AssembleParts(const ServerOptions& options);
  void StartGrpc(const ServerOptions& options, const std::shared_ptr<grpc::ServerCredentials>& credentials);
  void StartMetrics(const std::string& listen_address);
  void StartWebConsole(const ServerOptions& options);
  void GiveTheTickPathItsCpus(const std::vector<int>& cpus);  // --tick-cpus
  void RaiseTheTickPath(int priority);  // --rt-priority
  void BringBack();  // the data directory's trials, scores and sessions
  void CreateClassSessions(const ClassConfig& classes);

  std::unique_ptr<TickPool> pool_;  // declared first: destroyed after everything that wakes it
  std::unique_ptr<ServerDds> dds_;
  ViewerHub viewers_;  // before the registry, which tells it of every close
  std::unique_ptr<Persistence> persistence_;  // before the registry, which tells it of every close
  std::unique_ptr<SessionRegistry> registry_;
  std::unique_ptr<FramePump> pump_;
  ScoreBook scores_;
  TrialBook trials_;
  AccessPolicy policy_;
  std::unique_ptr<PeerLocator> peers_;  // before the service that asks them
  GrpcCallCounter grpc_calls_;  // outlives the gRPC server that calls into it
  std::unique_ptr<SessionServiceImpl> session_service_;
  std::unique_ptr<ViewerServiceImpl> viewer_service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<MetricsEndpoint> metrics_;  // after everything it reads: destroyed first
  std::unique_ptr<web::WebConsole> web_;      // a client of server_: stopped before it
  int bound_port_ = 0;
  bool shut_down_ = false;
};

}  // namespace hapsim::service
