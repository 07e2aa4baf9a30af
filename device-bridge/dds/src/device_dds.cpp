#include "hapsim/bridge/device_dds.h"

#include <cstring>

#include "hapsim/dds/partition.h"
#include "hapsim/wire/topics_wire.h"

namespace hapsim::bridge {

DeviceDds::Endpoints::Endpoints(const hapsim::dds::Participant& p, const std::string& partition)
    : pose_writer(p, &hapsim_dds_StylusPose_desc, hapsim::dds::kPoseTopic, partition),
      model_reader(p, &hapsim_dds_LocalForceModel_desc, hapsim::dds::kModelTopic, partition) {}

DeviceDds::DeviceDds(const hapsim::dds::Options& options, ModelRouter* router, std::function<void()> on_wake)
    : participant_(options), router_(router), on_wake_(std::move(on_wake)), io_(participant_) {
  devices_.reserve(router_->devices());
  for (std::size_t i = 0; i < router_->devices(); ++i) {
    auto e = std::make_unique<Endpoints>(participant_, hapsim::dds::SessionPartition(router_->session(i)));
    std::strncpy(e->wire.session, router_->session(i).c_str(), sizeof e->wire.session - 1);
    // Tag i + 1: 0 is the waitset's guard condition.
    e->read_condition = io_.AttachReader(e->model_reader.handle(), static_cast<dds_attach_t>(i + 1));
    devices_.push_back(std::move(e));
  }
}

DeviceDds::~DeviceDds() { Stop(); }

void DeviceDds::Start() {
  io_.Start({on_wake_, [this](dds_attach_t tag) { OnReader(tag); }});
}

void DeviceDds::Stop() { io_.Stop(); }

bool DeviceDds::WritePose(const SensedPose& pose) {
  // Unsigned wrap-around sends ids below the first past the end too.
  const std::size_t device = static_cast<std::uint32_t>(pose.device_id - router_->first_device_id());
  if (device >= devices_.size()) return false;
  Endpoints& e = *devices_[device];
  e.wire.device_id = pose.device_id;
  e.wire.seq = pose.seq;
  e.wire.t_device_ns = pose.t_device_ns;
  wire::PackPose(pose.tool, &e.wire);
  return e.pose_writer.Write(e.wire);
}

std::uint32_t DeviceDds::MatchedServers(std::size_t device) const {
  dds_publication_matched_status_t status{};
  if (dds_get_publication_matched_status(devices_[device]->pose_writer.handle(), &status) != DDS_RETCODE_OK) return 0;
  return status.current_count;
}

void DeviceDds::OnReader(dds_attach_t tag) {
  const auto device = static_cast<std::size_t>(tag - 1);
  if (device < devices_.size()) TakeAndRouteModels(devices_[device]->model_reader, *router_);
}

}  // namespace hapsim::bridge
