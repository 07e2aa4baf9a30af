// The server's DDS adapter: one I/O thread that sleeps on a waitset and
// routes incoming StylusPose samples (checked by FilterPose, then by the
// session's device ownership) to their sessions' pose mailboxes, waking each
// session in the tick pool at once — the device clocks its session. It finds
// sessions through the registry's copy-on-write table, never a lock that a
// control RPC holds. Force models are written by the tick workers themselves
// through WriteForceModel() (dds_write is thread-safe), with no hand-off.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "hapsim/runtime/dds.h"
#include "hapsim/service/pose_filter.h"
#include "hapsim/service/session_registry.h"
#include "haptics.h"

namespace hapsim::service {

struct ServerDdsCounters {
  std::atomic<std::uint64_t> poses_unknown_session{0};
  std::atomic<std::uint64_t> poses_other_device{0};  // session owned by another device
  std::atomic<std::uint64_t> poses_rejected{0};
  std::atomic<std::uint64_t> poses_accepted{0};
  std::atomic<std::uint64_t> force_models_written{0};
  std::atomic<std::uint64_t> write_failures{0};
};

class ServerDds {
 public:
  ServerDds(const runtime::DdsOptions& options, PoseLimits limits);
  ~ServerDds();

  void Start(SessionRegistry* registry, TickPool* pool);
  void Stop();
  void Wake() { waitset_.Wake(); }  // thread-safe
  // Thread-safe (tick workers); does not block on the network.
  bool WriteForceModel(const hapsim_dds_LocalForceModel& model);

  const ServerDdsCounters& counters() const { return counters_; }
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  void Run();
  void RoutePoses();

  runtime::DdsParticipant participant_;
  runtime::DdsReader<hapsim_dds_StylusPose> pose_reader_;
  runtime::DdsWriter<hapsim_dds_LocalForceModel> model_writer_;
  runtime::DdsWaitSet waitset_;
  PoseLimits limits_;
  SessionRegistry* registry_ = nullptr;
  TickPool* pool_ = nullptr;
  ServerDdsCounters counters_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::int64_t last_warning_ns_ = 0;
};

}  // namespace hapsim::service
