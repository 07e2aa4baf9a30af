// The server's DDS adapter. Every session has its own DDS partition
// (dds::SessionPartition(id)): a StylusPose reader and a LocalForceModel
// writer created with the session and deleted with it, so each bridge
// receives only its own session's models (no N² traffic) and a pose reaches
// only the session whose partition it was published in.
//
// One I/O thread (dds::IoThread) waits on every session's pose reader, each
// attached with the Session as its tag. On a wake it takes the triggered
// readers' poses, checks them (FilterPose, the sample's session id against
// the partition's, then the session's device ownership), puts the newest in
// the session's pose mailbox and wakes the session in the tick pool at once —
// the device clocks its session. It checks tags against the registry's
// copy-on-write table, never a lock that a control RPC holds. Force models
// are written by the tick workers through the session's port (dds_write is
// thread-safe), with no hand-off; the port packs the session's plain
// ForceModelMessage into the wire struct (inbound, FilterPose unpacks).
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "hapsim/dds/dds.h"
#include "hapsim/dds/io_thread.h"
#include "hapsim/service/pose_filter.h"
#include "hapsim/service/warning_limiter.h"
#include "hapsim/service/session_port.h"
#include "hapsim/service/session_registry.h"

namespace hapsim::service {

struct ServerDdsCounters {
  std::atomic<std::uint64_t> poses_rejected{0};       // malformed (FilterPose)
  std::atomic<std::uint64_t> poses_wrong_session{0};  // sample's session id differs from its partition's
  std::atomic<std::uint64_t> poses_other_device{0};   // session owned by another device
  std::atomic<std::uint64_t> poses_stale{0};          // duplicate / reordered / a second bridge with the owner's id
  std::atomic<std::uint64_t> poses_accepted{0};
  std::atomic<std::uint64_t> force_models_written{0};
  std::atomic<std::uint64_t> write_failures{0};
};

class ServerDds : public SessionTransport {
 public:
  ServerDds(const hapsim::dds::Options& options, PoseLimits limits);
  ~ServerDds() override;

  void Start(SessionRegistry* registry, TickPool* pool);
  void Stop();

  // SessionTransport: the session's reader and writer in its partition.
  std::shared_ptr<SessionPort> Open(const std::string& session_id) override;

  const ServerDdsCounters& counters() const { return counters_; }
  const std::string& config_origin() const { return participant_.config_origin(); }

 private:
  class Port;
  void RefreshIndex();
  void OnReader(dds_attach_t tag);
  void RoutePoses(Session& session, Port& port);  // each batch through RoutePoseBatch (pose_router.h)

  hapsim::dds::Participant participant_;
  PoseLimits limits_;
  SessionRegistry* registry_ = nullptr;
  TickPool* pool_ = nullptr;
  ServerDdsCounters counters_;
  WarningLimiter warnings_;  // I/O thread
  // I/O thread only: the table the tags are checked against, and its
  // sessions sorted by address.
  std::shared_ptr<const SessionTable> table_;
  std::vector<Session*> index_;
  hapsim::dds::IoThread io_;  // last: its thread uses the members above, so it stops first
};

}  // namespace hapsim::service
