// The server's DDS adapter: one I/O thread that sleeps on a waitset, routes
// incoming StylusPose samples (checked by FilterPose) to their sessions'
// mailboxes, and writes the force models the session ticks post. Session
// ticks only Publish() into mailboxes and Wake() this thread.
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
  std::atomic<std::uint64_t> poses_rejected{0};
  std::atomic<std::uint64_t> poses_accepted{0};
  std::atomic<std::uint64_t> force_models_written{0};
  std::atomic<std::uint64_t> write_failures{0};
};

class ServerDds {
 public:
  ServerDds(const runtime::DdsOptions& options, PoseLimits limits);
  ~ServerDds();

  void Start(SessionRegistry* registry);
  void Stop();
  void Wake() { waitset_.Wake(); }  // thread-safe

  const ServerDdsCounters& counters() const { return counters_; }
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  void Run();
  void RoutePoses();
  void WriteForceModels();

  runtime::DdsParticipant participant_;
  runtime::DdsReader<hapsim_dds_StylusPose> pose_reader_;
  runtime::DdsWriter<hapsim_dds_LocalForceModel> model_writer_;
  runtime::DdsWaitSet waitset_;
  PoseLimits limits_;
  SessionRegistry* registry_ = nullptr;
  ServerDdsCounters counters_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::int64_t last_warning_ns_ = 0;
};

}  // namespace hapsim::service
