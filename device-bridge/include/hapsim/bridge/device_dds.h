// The DDS side of one device (hapsim-bridge) or of many (hapsim-load): one
// participant, one StylusPose writer, one LocalForceModel reader. An I/O
// thread sleeps on a waitset; on every wake it runs the owner's hook, then
// routes the waiting force models, stamped with their arrival time on this
// process's clock, to the devices' inboxes (ModelRouter).
#pragma once
#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "hapsim/bridge/model_router.h"
#include "hapsim/runtime/dds.h"

namespace hapsim::bridge {

class DeviceDds {
 public:
  // on_wake runs on the I/O thread at every wake (Wake(), a model, or 5 ms).
  DeviceDds(const runtime::DdsOptions& options, ModelRouter* router, std::function<void()> on_wake = {});
  ~DeviceDds();
  DeviceDds(const DeviceDds&) = delete;
  DeviceDds& operator=(const DeviceDds&) = delete;

  void Start();
  void Stop();
  void Wake() { waitset_.Wake(); }  // thread-safe, cheap

  // False when DDS refused the sample. hapsim-bridge calls it from the I/O
  // thread (its on_wake hook), keeping DDS, which may allocate, out of the
  // servo tick. hapsim-load calls it from its servo thread: a load generator
  // measures the server, and skipping the hand-off to an I/O thread takes
  // one thread wake-up (up to a scheduler slice on a busy machine) out of
  // every round trip it reports.
  bool WritePose(const hapsim_dds_StylusPose& pose) { return pose_writer_.Write(pose); }
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  void Run();

  runtime::DdsParticipant participant_;
  runtime::DdsWriter<hapsim_dds_StylusPose> pose_writer_;
  runtime::DdsReader<hapsim_dds_LocalForceModel> model_reader_;
  runtime::DdsWaitSet waitset_;
  ModelRouter* router_;
  std::function<void()> on_wake_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace hapsim::bridge
