#include "hapsim/device_link/server_dds.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include "hapsim/common/clock.h"
#include "hapsim/dds/partition.h"
#include "hapsim/dds/topics.h"
#include "hapsim/device_link/pose_router.h"
#include "hapsim/wire/topics_wire.h"

namespace hapsim::service {

namespace {

// The header is this server's; the body goes through hapsim::wire.
void Pack(const ForceModelMessage& in, hapsim_dds_LocalForceModel& out) {
  out.device_id = in.device_id;
  out.seq = in.seq;
  out.echo_pose_seq = in.echo_pose_seq;
  out.t_server_ns = in.t_server_ns;
  out.echo_pose_held_us =
      static_cast<std::uint32_t>(std::clamp<std::int64_t>(in.echo_pose_held_ns / 1000, 0, UINT32_MAX));
  out.next_model_within_ms =
      static_cast<std::uint32_t>(std::clamp(std::lround(in.next_model_within_s * 1e3), 0L, 60'000L));
  wire::PackForceModel(in.model, in.tool_force_W_N, &out);
}

}  // namespace

// One session's endpoints in its partition.
class ServerDds::Port : public SessionPort {
 public:
  Port(ServerDds* owner, const std::string& session_id)
      : owner_(owner),
        pose_reader_(owner->participant_, &hapsim_dds_StylusPose_desc, hapsim::dds::kPoseTopic,
                     hapsim::dds::SessionPartition(session_id)),
        model_writer_(owner->participant_, &hapsim_dds_LocalForceModel_desc, hapsim::dds::kModelTopic,
                      hapsim::dds::SessionPartition(session_id)) {
    // The session id is the same in every model: written once (NUL-padded).
    session_id.copy(wire_.session, sizeof wire_.session - 1);
    wire_.server_instance = owner->instance_;
  }

  // Tick worker (one at a time): packs into the port's own wire struct, so
  // nothing is allocated.
  bool WriteForceModel(const ForceModelMessage& message) override {
    Pack(message, wire_);
    if (model_writer_.Write(wire_)) {
      owner_->counters_.force_models_written.fetch_add(1, std::memory_order_relaxed);
      return true;
    }
    owner_->counters_.write_failures.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  // The port itself is its reader's tag: a wake names the port, and the
  // port knows its session.
  void StartReceiving(Session* session) override {
    session_ = session;
    condition_ = owner_->io_.AttachReader(pose_reader_.handle(), TagOf(this));
  }
  void StopReceiving() override { condition_.Reset(); }  // deleting the condition detaches it

  static dds_attach_t TagOf(SessionPort* port) { return reinterpret_cast<dds_attach_t>(port); }
  Session& session() const { return *session_; }
  hapsim::dds::PoseReader& pose_reader() { return pose_reader_; }

 private:
  ServerDds* owner_;
  Session* session_ = nullptr;  // set before the reader is attached
  hapsim::dds::PoseReader pose_reader_;
  hapsim::dds::ModelWriter model_writer_;
  hapsim_dds_LocalForceModel wire_{};
  hapsim::dds::Entity condition_;
};

namespace {
std::uint64_t RandomInstanceId() {
  std::random_device device;
  std::uint64_t id = 0;
  while (id == 0) id = (static_cast<std::uint64_t>(device()) << 32) | device();
  return id;
}
}  // namespace

ServerDds::ServerDds(const hapsim::dds::Options& options, PoseLimits limits,
                     hapsim::dds::IoThread::Scheduling io_scheduling)
    : participant_(options),
      instance_(RandomInstanceId()),
      limits_(limits),
      publications_(participant_),
      io_(participant_, hapsim::dds::IoThread::kDefaultWakeTimeoutNs, io_scheduling) {}

ServerDds::~ServerDds() { Stop(); }

std::shared_ptr<SessionPort> ServerDds::Open(const std::string& session_id) {
  return std::make_shared<Port>(this, session_id);
}

void ServerDds::Start(SessionRegistry* registry, TickPool* pool) {
  registry_ = registry;
  pool_ = pool;
  // Every wake refreshes the table first: it holds the sessions it names
  // alive for the pass.
  publications_condition_ = io_.AttachReader(publications_.handle(), kPublicationsTag);
  io_.Start({[this] { RefreshIndex(); }, [this](dds_attach_t tag) { OnReader(tag); }});
}

void ServerDds::Stop() {
  io_.Stop();
  publications_condition_.Reset();
  table_.reset();
  index_.clear();
}

void ServerDds::RefreshIndex() {
  auto table = registry_->Table();
  if (table == table_) return;
  table_ = std::move(table);
  index_.clear();
  for (const auto& [id, session] : *table_) index_.push_back(Port::TagOf(&session->port()));
  std::sort(index_.begin(), index_.end());
  CheckForeignModelWriters();  // a new session may share its id with another server's
}

void ServerDds::OnReader(dds_attach_t tag) {
  if (tag == kPublicationsTag) {
    TakePublications();
    return;
  }
  // A tag is trusted only if its session is in the table we hold (a closing
  // session is removed from the table before its reader is detached, a new
  // one attached after it is published). Every session's port is a Port:
  // this transport opened it.
  if (!std::binary_search(index_.begin(), index_.end(), tag)) return;
  Port& port = *static_cast<Port*>(reinterpret_cast<SessionPort*>(tag));
  RoutePoses(port.session(), port);
}

void ServerDds::TakePublications() {
  bool changed = false;
  publications_.Take([&](const hapsim::dds::RemotePublication& pub) {
    if (!pub.alive) {
      changed |= foreign_model_writers_.erase(pub.handle) > 0;
      std::erase_if(warned_, [&](const auto& pair) { return pair.first == pub.handle; });
    } else if (pub.topic == hapsim::dds::kModelTopic) {
      foreign_model_writers_[pub.handle] = pub;
      changed = true;
    }
  });
  if (changed) CheckForeignModelWriters();
}

void ServerDds::CheckForeignModelWriters() {
  if (!table_) return;
  if (foreign_model_writers_.empty()) {  // the usual case: no other server, nothing to match
    warned_.clear();
    counters_.foreign_model_writers.store(0, std::memory_order_relaxed);
    return;
  }
  // A session closed and opened again against the same writer is warned again.
  std::erase_if(warned_, [&](const auto& pair) { return table_->find(pair.second) == table_->end(); });
  std::uint64_t count = 0;
  for (const auto& [id, session] : *table_) {
    const std::string partition = hapsim::dds::SessionPartition(id);
    for (const auto& [handle, pub] : foreign_model_writers_) {
      if (std::find(pub.partitions.begin(), pub.partitions.end(), partition) == pub.partitions.end()) continue;
      ++count;
      if (warned_.emplace(handle, id).second) {
        spdlog::warn(
            "another server (DDS participant {:016x}) publishes force models for session '{}' in its "
            "partition {}: a stylus driving '{}' follows whichever server answers first. Give each server "
            "its own --dds-domain",
            pub.participant_prefix, id, partition, id);
      }
    }
  }
  counters_.foreign_model_writers.store(count, std::memory_order_relaxed);
}

void ServerDds::RoutePoses(Session& session, Port& port) {
  std::array<hapsim_dds_StylusPose, 64> batch;
  for (;;) {
    const std::size_t n = port.pose_reader().Take(batch);
    if (n == 0) return;
    const std::int64_t now = common::SteadyNowNs();
    if (RoutePoseBatch(session, std::span(batch.data(), n), limits_, now, &counters_, &warnings_)) {
      pool_->Wake(&session, session.PoseDueNs(now));
    }
    if (n < batch.size()) return;
  }
}

}  // namespace hapsim::service
