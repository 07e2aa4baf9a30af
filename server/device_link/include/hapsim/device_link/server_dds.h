// The server's DDS adapter. Every session has its own DDS partition
// (dds::SessionPartition(id)): a StylusPose reader and a LocalForceModel
// writer created with the session and deleted with it, so each bridge
// receives only its own session's models (no N² traffic) and a pose reaches
// only the session whose partition it was published in.
//
// One I/O thread (dds::IoThread) waits on every session's pose reader, each
// attached with its port (the session's endpoints) as its tag. On a wake it takes the triggered
// readers' poses, checks them (FilterPose, the sample's session id against
// the partition's, then the session's device ownership), puts the newest in
// the session's pose mailbox and wakes the session in the tick pool at once —
// the device clocks its session. It checks tags against the registry's
// copy-on-write table, never a lock that a control RPC holds. Force models
// are written by the tick workers through the session's port (dds_write is
// thread-safe), with no hand-off; the port packs the session's plain
// ForceModelMessage into the wire struct (inbound, FilterPose unpacks).
//
// Every model carries this server's instance id (random, fixed at start), so
// a bridge follows one server even if another on the domain serves the same
// session id. The I/O thread also watches DDS discovery and warns when
// another participant publishes force models in one of our sessions'
// partitions — the stylus of that session would otherwise get both.
#pragma once
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "hapsim/dds/dds.h"
#include "hapsim/dds/io_thread.h"
#include "hapsim/dds/publication_watch.h"
#include "hapsim/device_link/pose_filter.h"
#include "hapsim/device_link/warning_limiter.h"
#include "hapsim/runtime/session_port.h"
#include "hapsim/runtime/session_registry.h"

namespace hapsim::service {

struct ServerDdsCounters {
  std::atomic<std::uint64_t> poses_rejected{0};       // malformed (FilterPose)
  std::atomic<std::uint64_t> poses_wrong_session{0};  // sample's session id differs from its partition's
  std::atomic<std::uint64_t> poses_other_device{0};   // session owned by another device
  std::atomic<std::uint64_t> poses_stale{0};          // duplicate / reordered / a second bridge with the owner's id
  std::atomic<std::uint64_t> poses_accepted{0};
  std::atomic<std::uint64_t> force_models_written{0};
  std::atomic<std::uint64_t> write_failures{0};
  // Now: another participant's force-model writers in our sessions' partitions (one per writer and session).
  std::atomic<std::uint64_t> foreign_model_writers{0};
};

class ServerDds : public SessionTransport {
 public:
  // io_scheduling: of the thread that takes the poses and wakes their
  // sessions (IoThread::Scheduling; ServerOptions::dds_io_scheduling).
  ServerDds(const hapsim::dds::Options& options, PoseLimits limits, hapsim::dds::IoThread::Scheduling io_scheduling);
  ~ServerDds() override;

  void Start(SessionRegistry* registry, TickPool* pool);
  void Stop();

  // SessionTransport: the session's reader and writer in its partition.
  std::shared_ptr<SessionPort> Open(const std::string& session_id) override;

  const ServerDdsCounters& counters() const { return counters_; }
  const std::string& config_origin() const { return participant_.config_origin(); }
  // Random, fixed for this server's life; in every force model it sends.
  std::uint64_t instance() const { return instance_; }

 private:
  class Port;
  void RefreshIndex();
  void OnReader(dds_attach_t tag);
  void RoutePoses(Session& session, Port& port);  // each batch through RoutePoseBatch (pose_router.h)
  void TakePublications();
  void CheckForeignModelWriters();

  // The discovery reader's tag: never a port's address, nor the guard's 0.
  static constexpr dds_attach_t kPublicationsTag = 1;

  hapsim::dds::Participant participant_;
  std::uint64_t instance_;
  PoseLimits limits_;
  SessionRegistry* registry_ = nullptr;
  TickPool* pool_ = nullptr;
  ServerDdsCounters counters_;
  WarningLimiter warnings_;  // I/O thread
  // I/O thread only: the table the tags are checked against, and its
  // sessions' port tags, sorted.
  std::shared_ptr<const SessionTable> table_;
  std::vector<dds_attach_t> index_;
  // I/O thread only: other participants' force-model writers by discovery
  // instance, and the (writer, session) pairs already warned about.
  hapsim::dds::PublicationWatch publications_;
  hapsim::dds::Entity publications_condition_;
  std::map<dds_instance_handle_t, hapsim::dds::RemotePublication> foreign_model_writers_;
  std::set<std::pair<dds_instance_handle_t, std::string>> warned_;
  hapsim::dds::IoThread io_;  // last: its thread uses the members above, so it stops first
};

}  // namespace hapsim::service
