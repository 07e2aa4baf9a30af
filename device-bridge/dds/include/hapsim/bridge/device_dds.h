// The DDS side of one device (hapsim-bridge) or of many (hapsim-load): one
// participant and, per device, a StylusPose writer and a LocalForceModel
// reader in the DDS partition of the device's session
// (dds::SessionPartition), so a device receives only its own session's
// models and its poses reach only that session. An I/O thread sleeps on a
// waitset; on every wake it runs the owner's hook, then routes the waiting
// force models of the triggered readers, stamped with their arrival time on
// this process's clock, to the devices' inboxes (ModelRouter). Poses go out
// and models come in as core types: the IDL structs stay on this side. A session is
// fixed for the life of the endpoints (Cyclone cannot change a partition
// after creation): to drive another session, make a new DeviceDds.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hapsim/bridge/model_router.h"
#include "hapsim/dds/dds.h"
#include "hapsim/dds/io_thread.h"
#include "hapsim/dds/topics.h"

namespace hapsim::bridge {

class DeviceDds {
 public:
  // One device per router slot (id router->first_device_id() + i, session
  // router->session(i)). on_wake runs on the I/O thread at every wake
  // (Wake(), a model, or 5 ms).
  DeviceDds(const hapsim::dds::Options& options, ModelRouter* router, std::function<void()> on_wake = {});
  ~DeviceDds();
  DeviceDds(const DeviceDds&) = delete;
  DeviceDds& operator=(const DeviceDds&) = delete;

  void Start();
  void Stop();
  void Wake() { io_.Wake(); }  // thread-safe, cheap

  // Writes on the writer of the pose's device (by pose.device_id). False
  // when DDS refused the sample or the device is not ours. hapsim-bridge
  // calls it from the I/O thread (its on_wake hook), keeping DDS, which may
  // allocate, out of the servo tick. hapsim-load calls it from its servo
  // thread: a load generator measures the server, and skipping the hand-off
  // to an I/O thread takes one thread wake-up (up to a scheduler slice on a
  // busy machine) out of every round trip it reports.
  bool WritePose(const SensedPose& pose);
  // Servers matched by device's pose writer (0: no server serves its session yet).
  std::uint32_t MatchedServers(std::size_t device) const;
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  struct Endpoints {
    Endpoints(const hapsim::dds::Participant& p, const std::string& partition);
    hapsim::dds::PoseWriter pose_writer;
    hapsim::dds::ModelReader model_reader;
    hapsim::dds::Entity read_condition;
    hapsim_dds_StylusPose wire{};  // the session field filled once; written by one thread at a time
  };
  void OnReader(dds_attach_t tag);

  hapsim::dds::Participant participant_;
  ModelRouter* router_;
  std::function<void()> on_wake_;
  hapsim::dds::IoThread io_;
  std::vector<std::unique_ptr<Endpoints>> devices_;  // one per router slot; detached before io_ goes
};

}  // namespace hapsim::bridge
