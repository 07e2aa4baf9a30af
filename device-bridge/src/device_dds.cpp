#include "hapsim/bridge/device_dds.h"

namespace hapsim::bridge {

DeviceDds::DeviceDds(const runtime::DdsOptions& options, ModelRouter* router, std::function<void()> on_wake)
    : participant_(options),
      pose_writer_(participant_, &hapsim_dds_StylusPose_desc, "hapsim_StylusPose"),
      model_reader_(participant_, &hapsim_dds_LocalForceModel_desc, "hapsim_LocalForceModel"),
      waitset_(participant_),
      router_(router),
      on_wake_(std::move(on_wake)) {
  waitset_.AttachReader(model_reader_.handle());
}

DeviceDds::~DeviceDds() { Stop(); }

void DeviceDds::Start() {
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
}

void DeviceDds::Stop() {
  stop_ = true;
  waitset_.Wake();
  if (thread_.joinable()) thread_.join();
}

void DeviceDds::Run() {
  while (!stop_.load()) {
    waitset_.Wait(5'000'000);
    if (on_wake_) on_wake_();
    TakeAndRouteModels(model_reader_, *router_);
  }
}

}  // namespace hapsim::bridge
