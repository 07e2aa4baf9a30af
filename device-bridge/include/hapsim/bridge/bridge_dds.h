// The bridge's DDS adapter: an I/O thread that writes the poses the servo
// loop posts and takes the force models addressed to this device and
// session, stamping their arrival with the bridge's clock (Cyclone's lifespan
// QoS counts from local receive time, so age is measured here).
#pragma once
#include <atomic>
#include <string>
#include <thread>

#include "hapsim/bridge/servo_loop.h"
#include "hapsim/runtime/dds.h"

namespace hapsim::bridge {

class BridgeDds {
 public:
  BridgeDds(const runtime::DdsOptions& options, std::uint32_t device_id, std::string session);
  ~BridgeDds();
  void Start();
  void Stop();
  void Wake() { waitset_.Wake(); }

  runtime::LatestValue<hapsim_dds_StylusPose>& pose_outbox() { return pose_outbox_; }
  runtime::LatestValue<ReceivedModel>& model_inbox() { return model_inbox_; }
  std::uint64_t poses_written() const { return poses_written_.load(); }
  std::uint64_t models_for_others() const { return models_for_others_.load(); }
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  void Run();

  runtime::DdsParticipant participant_;
  runtime::DdsWriter<hapsim_dds_StylusPose> pose_writer_;
  runtime::DdsReader<hapsim_dds_LocalForceModel> model_reader_;
  runtime::DdsWaitSet waitset_;
  std::uint32_t device_id_;
  std::string session_;
  runtime::LatestValue<hapsim_dds_StylusPose> pose_outbox_;
  runtime::LatestValue<ReceivedModel> model_inbox_;
  std::atomic<std::uint64_t> poses_written_{0}, models_for_others_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hapsim::bridge
