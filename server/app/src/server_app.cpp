#include "hapsim/app/server_app.h"

#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include "hapsim/common/flags.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/dds/io_thread.h"

namespace hapsim::service {

namespace {

std::string ReadPem(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string("cannot read ") + what + " " + path);
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().find("-----BEGIN") == std::string::npos) {
    throw std::runtime_error(std::string(what) + " " + path + " is not a PEM file");
  }
  return text.str();
}

std::shared_ptr<grpc::ServerCredentials> MakeCredentials(const ServerOptions& o) {
  if (o.tls_cert_file.empty() != o.tls_key_file.empty()) {
    throw std::runtime_error("TLS needs both a certificate and its key (--tls-cert and --tls-key)");
  }
  if (o.tls_cert_file.empty()) {
    if (!o.tls_client_ca_file.empty()) throw std::runtime_error("--tls-client-ca needs --tls-cert and --tls-key");
    return grpc::InsecureServerCredentials();
  }
  grpc::SslServerCredentialsOptions ssl;
  ssl.pem_key_cert_pairs.push_back({ReadPem(o.tls_key_file, "TLS key"), ReadPem(o.tls_cert_file, "TLS certificate")});
  if (!o.tls_client_ca_file.empty()) {
    ssl.pem_root_certs = ReadPem(o.tls_client_ca_file, "client CA");
    ssl.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  }
  return grpc::SslServerCredentials(ssl);
}

std::unique_ptr<PeerLocator> MakePeerLocator(const DirectoryOptions& d) {
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (!d.peer_tls_ca_file.empty()) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = ReadPem(d.peer_tls_ca_file, "peer TLS CA");
    credentials = grpc::SslCredentials(ssl);
  }
  if (!d.directory.Find(d.server_name)) {
    spdlog::warn(
        "this server ('{}') is not in the directory: other servers will not ask it where sessions are "
        "(set --server-name to its name there)",
        d.server_name);
  }
  spdlog::info("directory: {} servers; this is '{}'; the others are asked with a {} ms timeout{}",
               d.directory.servers.size(), d.server_name, d.peer_timeout.count(),
               d.peer_tls_ca_file.empty() ? " over plain TCP" : " over TLS");
  return std::make_unique<PeerLocator>(d.directory, d.server_name, std::move(credentials), d.peer_timeout);
}

// How the server listens, and a loud warning when that is unsafe.
void LogServerListening(const ServerOptions& o, int bound_port) {
  const bool tls = !o.tls_cert_file.empty();
  spdlog::info("hapsim-server listening on {} (port {}; {}; {})", o.listen_address, bound_port,
               tls ? (o.tls_client_ca_file.empty() ? "TLS" : "TLS with client certificates") : "plain TCP",
               o.classes ? "tokens required" : "no auth: development mode");
  if (!IsLoopbackAddress(o.listen_address) && !o.classes) {
    spdlog::warn(
        "*** NO AUTHENTICATION on {}: anyone who reaches this port can create, reset, close and watch "
        "every session. Give a --class-config (and TLS) unless this network is yours alone. ***",
        o.listen_address);
  }
  if (!IsLoopbackAddress(o.listen_address) && o.classes && !tls) {
    spdlog::warn("*** tokens travel in plain text on {}: add --tls-cert/--tls-key ***", o.listen_address);
  }
}

}  // namespace

bool IsLoopbackAddress(const std::string& a) {
  return a.rfind("127.", 0) == 0 || a.rfind("localhost:", 0) == 0 || a.rfind("[::1]:", 0) == 0 ||
         a.rfind("ipv4:127.", 0) == 0;
}

ServerApp::ServerApp(const ServerOptions& o) : policy_(o.classes ? AccessPolicy(*o.classes) : AccessPolicy()) {
  const auto credentials = MakeCredentials(o);  // bad TLS files fail before anything starts
  if (const std::string why = o.tick_cpus.empty() ? "" : common::CheckTickCpus(o.tick_cpus); !why.empty()) {
    throw std::invalid_argument("--tick-cpus: " + why);
  }
  if (o.directory) peers_ = MakePeerLocator(*o.directory);
  AssembleParts(o);
  StartGrpc(o, credentials);
  if (!o.metrics_listen_address.empty()) StartMetrics(o.metrics_listen_address);
  if (!o.web_listen_address.empty()) StartWebConsole(o);
  dds_->Start(registry_.get(), pool_.get());
  if (o.rt_priority > 0) RaiseTheTickPath(o.rt_priority);
  if (!o.tick_cpus.empty()) GiveTheTickPathItsCpus(o.tick_cpus);
  if (persistence_) BringBack();
  pump_->Start();
  if (o.classes) CreateClassSessions(*o.classes);
  LogServerListening(o, bound_port_);
}

void ServerApp::AssembleParts(const ServerOptions& o) {
  dds_ = std::make_unique<ServerDds>(o.dds, o.pose_limits, o.dds_io_scheduling);
  spdlog::info("DDS domain {} with config: {}; server instance {:016x}", o.dds.domain_id, dds_->config_origin(),
               dds_->instance());
  const int default_workers = o.tick_cpus.empty() ? DefaultWorkerCount() : static_cast<int>(o.tick_cpus.size());
  pool_ = std::make_unique<TickPool>(o.workers > 0 ? o.workers : default_workers, TickPool::kDefaultCoalesceNs,
                                     o.tick_wait);
  spdlog::info("tick pool: {} workers (--tick-wait {})", pool_->workers(), common::IdleWaitName(o.tick_wait));
  if (o.persistence) persistence_ = std::make_unique<Persistence>(*o.persistence, &policy_, &viewers_);
  registry_ = std::make_unique<SessionRegistry>(
      o.sessions, pool_.get(), dds_.get(), persistence_ ? static_cast<SessionListener*>(persistence_.get()) : &viewers_,
      persistence_ ? persistence_->ListenerFactory() : FollowTrials(&policy_));
  pump_ = std::make_unique<FramePump>(registry_.get(), &viewers_, [this](const SessionTable& sessions) {
    trials_.Observe(sessions);
    if (persistence_) persistence_->MaybeApplyRetention();
  });
  session_service_ =
      std::make_unique<SessionServiceImpl>(registry_.get(), &viewers_, &scores_, &policy_, o.dds.domain_id, &trials_,
                                           persistence_ ? &persistence_->store() : nullptr,
                                           persistence_ ? persistence_->recordings_dir() : std::string(), peers_.get());
  viewer_service_ = std::make_unique<ViewerServiceImpl>(registry_.get(), &viewers_, o.quantum_m, &policy_);
}

void ServerApp::StartGrpc(const ServerOptions& o, const std::shared_ptr<grpc::ServerCredentials>& credentials) {
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  builder.AddListeningPort(o.listen_address, credentials, &bound_port_);
  builder.RegisterService(session_service_.get());
  builder.RegisterService(viewer_service_.get());
  builder.SetMaxReceiveMessageSize(o.max_message_bytes);
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  interceptors.push_back(grpc_calls_.MakeInterceptorFactory());
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  // Small HTTP/2 write buffer: OnWriteDone then means "nearly delivered", so a
  // slow viewer gets coalesced frames instead of a seconds-long backlog.
  builder.AddChannelArgument(GRPC_ARG_HTTP2_WRITE_BUFFER_SIZE, 16 * 1024);
  server_ = builder.BuildAndStart();
  if (!server_ || bound_port_ == 0) {
    throw std::runtime_error("cannot listen on " + o.listen_address +
                             " (address in use or invalid? choose another with --listen)");
  }
}

void ServerApp::StartMetrics(const std::string& listen_address) {
  metrics_ = std::make_unique<MetricsEndpoint>(listen_address, [this] {
    return FormatMetrics(*registry_, dds_->counters(), pool_->stats(), &grpc_calls_,
                         policy_.enabled() ? &policy_.counters() : nullptr);
  });
  spdlog::info("metrics at http://{}/metrics (port {})", listen_address, metrics_->bound_port());
}

void ServerApp::StartWebConsole(const ServerOptions& o) {
  web::WebConsoleOptions w;
  w.listen_address = o.web_listen_address;
  w.root_dir = o.web_root;
  w.tls_cert_file = o.tls_cert_file;
  w.tls_key_file = o.tls_key_file;
  w.tls_client_ca_file = o.tls_client_ca_file;
  w.server_version = common::VersionLine("hapsim-server");
  if (!w.server_version.empty() && w.server_version.back() == '\n') w.server_version.pop_back();
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(-1);  // keyframes of the largest scenes; the browser's requests are bounded
  try {
    web_ = std::make_unique<web::WebConsole>(w, server_->InProcessChannel(args), &policy_);
  } catch (const std::exception&) {
    Shutdown();
    throw;
  }
  const bool plain_off_loopback = !web_->tls() && !IsLoopbackAddress(o.web_listen_address);
  if (plain_off_loopback) {
    spdlog::warn("web console on {} WITHOUT TLS: tokens cross the network in the clear (give --tls-cert/--tls-key)",
                 o.web_listen_address);
  }
  spdlog::info("web console at {}://{} (port {}), serving {}", web_->tls() ? "https" : "http", o.web_listen_address,
               web_->bound_port(), o.web_root);
}

void ServerApp::RaiseTheTickPath(int priority) {
  // The DDS threads (a pose's way in) one above the ticks they wake: routing
  // it is short, and a busy tick must not hold up another session's pose.
  const auto ticks = common::RaiseThreadsNamed({TickPool::kWorkerThreadName}, priority);
  const auto dds_threads = dds::RaiseDdsThreads(priority + 1);
  if (ticks.refused + dds_threads.refused > 0 || ticks.raised == 0) {
    spdlog::warn(
        "real-time priority refused for {} of {} threads (needs CAP_SYS_NICE or LimitRTPRIO >= {}): the "
        "tick runs at normal priority, where viewers and gRPC compete with it",
        ticks.refused + dds_threads.refused, ticks.raised + dds_threads.raised + ticks.refused + dds_threads.refused,
        priority + 1);
    return;
  }
  spdlog::info("real-time priority: {} tick workers at SCHED_FIFO {}, {} DDS threads at {}", ticks.raised, priority,
               dds_threads.raised, priority + 1);
}

void ServerApp::GiveTheTickPathItsCpus(const std::vector<int>& cpus) {
  const auto split = common::SplitThreadsByCpu(
      [](const std::string& name) { return name == TickPool::kWorkerThreadName || dds::IsDdsThread(name); }, cpus);
  if (split.refused > 0) {
    spdlog::warn("CPU affinity refused for {} threads: they may share the tick's CPUs", split.refused);
  }
  std::string list;
  for (const int cpu : cpus) list += (list.empty() ? "" : ",") + std::to_string(cpu);
  spdlog::info("tick CPUs {}: {} tick workers and DDS threads there, {} other threads on the other CPUs", list,
               split.tick_path, split.others);
}

void ServerApp::BringBack() {
  try {
    persistence_->BringBack(*registry_, trials_, scores_);
  } catch (const std::exception& e) {
    Shutdown();
    throw std::runtime_error(std::string("cannot bring back the data directory's sessions: ") + e.what());
  }
}

void ServerApp::CreateClassSessions(const ClassConfig& classes) {
  for (const auto& warning : classes.warnings) spdlog::warn("class config: {}", warning);
  try {
    for (const auto& cls : classes.classes) {
      for (const auto& s : cls.sessions) {
        if (!registry_->Find(s.id)) registry_->Create(s.id, s.scene, s.trainee, {});  // else: brought back
      }
      spdlog::info("class '{}': {} sessions", cls.name, cls.sessions.size());
    }
  } catch (const std::exception& e) {
    Shutdown();  // everything started above stops before the error leaves
    throw std::runtime_error(std::string("cannot create the class config's sessions: ") + e.what());
  }
}

ServerApp::~ServerApp() { Shutdown(); }

void ServerApp::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  metrics_.reset();  // no scrape reads the registry while it closes
  if (web_) web_->Stop();    // its calls end before the services they call stop
  session_service_->Stop();  // class views end before the gRPC server waits for its calls
  pump_->Stop();
  // What is recorded so far is written before the sessions close, so their
  // trials stay open and a restarted server brings them back.
  if (persistence_) persistence_->Stop();
  registry_->CloseAll();  // stops ticks and ends every viewer stream
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
  server_->Wait();
  dds_->Stop();
  pool_->Stop();
}

}  // namespace hapsim::service
