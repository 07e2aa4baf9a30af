#include "hapsim/service/server_app.h"

#include <chrono>

#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

namespace hapsim::service {

ServerApp::ServerApp(const ServerOptions& o) {
  dds_ = std::make_unique<ServerDds>(o.dds, o.pose_limits);
  spdlog::info("DDS domain {} with config: {}", o.dds.domain_id, dds_->config_origin());
  pool_ = std::make_unique<TickPool>(o.workers > 0 ? o.workers : DefaultWorkerCount());
  spdlog::info("tick pool: {} workers", pool_->workers());
  registry_ = std::make_unique<SessionRegistry>(o.sessions, pool_.get(), dds_.get(), &viewers_);
  pump_ = std::make_unique<FramePump>(registry_.get(), &viewers_);
  session_service_ = std::make_unique<SessionServiceImpl>(registry_.get(), &viewers_, &scores_);
  viewer_service_ = std::make_unique<ViewerServiceImpl>(registry_.get(), &viewers_, o.quantum_m);

  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  builder.AddListeningPort(o.listen_address, grpc::InsecureServerCredentials(), &bound_port_);
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
  if (!o.metrics_listen_address.empty()) {
    metrics_ = std::make_unique<MetricsEndpoint>(o.metrics_listen_address, [this] {
      return FormatMetrics(*registry_, dds_->counters(), pool_->stats(), &grpc_calls_);
    });
    spdlog::info("metrics at http://{}/metrics (port {})", o.metrics_listen_address, metrics_->bound_port());
  }
  dds_->Start(registry_.get(), pool_.get());
  pump_->Start();
  spdlog::info("hapsim-server listening on {} (port {})", o.listen_address, bound_port_);
}

ServerApp::~ServerApp() { Shutdown(); }

void ServerApp::Shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  metrics_.reset();  // no scrape reads the registry while it closes
  pump_->Stop();
  registry_->CloseAll();  // stops ticks and ends every viewer stream
  server_->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(2));
  server_->Wait();
  dds_->Stop();
  pool_->Stop();
}

}  // namespace hapsim::service
