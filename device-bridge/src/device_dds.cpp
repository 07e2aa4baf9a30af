#include "hapsim/bridge/device_dds.h"

#include <array>

namespace hapsim::bridge {

DeviceDds::Endpoints::Endpoints(const runtime::DdsParticipant& p, const std::string& partition)
    : pose_writer(p, &hapsim_dds_StylusPose_desc, "hapsim_StylusPose", partition),
      model_reader(p, &hapsim_dds_LocalForceModel_desc, "hapsim_LocalForceModel", partition) {}

DeviceDds::DeviceDds(const runtime::DdsOptions& options, ModelRouter* router, std::function<void()> on_wake)
    : participant_(options), waitset_(participant_), router_(router), on_wake_(std::move(on_wake)) {
  devices_.reserve(router_->devices());
  for (std::size_t i = 0; i < router_->devices(); ++i) {
    auto e = std::make_unique<Endpoints>(participant_, runtime::SessionPartition(router_->session(i)));
    // Tag i + 1: 0 is the waitset's guard condition.
    e->read_condition = waitset_.AttachReader(e->model_reader.handle(), static_cast<dds_attach_t>(i + 1));
    devices_.push_back(std::move(e));
  }
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

bool DeviceDds::WritePose(const hapsim_dds_StylusPose& pose) {
  // Unsigned wrap-around sends ids below the first past the end too.
  const std::size_t device = static_cast<std::uint32_t>(pose.device_id - router_->first_device_id());
  if (device >= devices_.size()) return false;
  return devices_[device]->pose_writer.Write(pose);
}

std::uint32_t DeviceDds::MatchedServers(std::size_t device) const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(devices_[device]->pose_writer.handle(), &status) != DDS_RETCODE_OK) return 0;
  return status.current_count;
}

void DeviceDds::Run() {
  std::array<dds_attach_t, 64> tags;
  while (!stop_.load()) {
    const std::size_t n = waitset_.Wait(5'000'000, tags);
    if (on_wake_) on_wake_();
    for (std::size_t i = 0; i < n; ++i) {
      if (tags[i] == runtime::DdsWaitSet::kGuardTag) continue;
      const auto device = static_cast<std::size_t>(tags[i] - 1);
      if (device < devices_.size()) TakeAndRouteModels(devices_[device]->model_reader, *router_);
    }
  }
}

}  // namespace hapsim::bridge
