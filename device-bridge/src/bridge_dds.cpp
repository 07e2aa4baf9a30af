#include "hapsim/bridge/bridge_dds.h"

#include <array>
#include <cstring>

#include "hapsim/runtime/clock.h"

namespace hapsim::bridge {

BridgeDds::BridgeDds(const runtime::DdsOptions& options, std::uint32_t device_id, std::string session)
    : participant_(options),
      pose_writer_(participant_, &hapsim_dds_StylusPose_desc, "hapsim_StylusPose"),
      model_reader_(participant_, &hapsim_dds_LocalForceModel_desc, "hapsim_LocalForceModel"),
      waitset_(participant_),
      device_id_(device_id),
      session_(std::move(session)) {
  waitset_.AttachReader(model_reader_.handle());
}

BridgeDds::~BridgeDds() { Stop(); }

void BridgeDds::Start() {
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
}

void BridgeDds::Stop() {
  stop_ = true;
  waitset_.Wake();
  if (thread_.joinable()) thread_.join();
}

void BridgeDds::Run() {
  std::array<hapsim_dds_LocalForceModel, 16> models;
  hapsim_dds_StylusPose pose;
  while (!stop_.load()) {
    waitset_.Wait(5'000'000);
    if (pose_outbox_.TakeIfNew(&pose) && pose_writer_.Write(pose)) poses_written_.fetch_add(1);
    for (;;) {
      const std::size_t n = model_reader_.Take(models);
      const std::int64_t now = runtime::SteadyNowNs();
      for (std::size_t i = 0; i < n; ++i) {
        const auto& m = models[i];
        if (m.device_id != device_id_ || std::strncmp(m.session, session_.c_str(), sizeof m.session) != 0) {
          models_for_others_.fetch_add(1);
          continue;
        }
        model_inbox_.Publish(ReceivedModel{m, now});
      }
      if (n < models.size()) break;
    }
  }
}

}  // namespace hapsim::bridge
