#include "hapsim/service/server_dds.h"

#include <algorithm>
#include <array>

#include <spdlog/spdlog.h>

#include "hapsim/common/clock.h"
#include "hapsim/dds/partition.h"
#include "hapsim/dds/topics.h"
#include "hapsim/service/pose_router.h"

namespace hapsim::service {

namespace {

void Pack(const ForceModelMessage& in, hapsim_dds_LocalForceModel& out) {
  out.device_id = in.device_id;
  out.seq = in.seq;
  out.echo_pose_seq = in.echo_pose_seq;
  out.t_server_ns = in.t_server_ns;
  out.state = static_cast<std::uint8_t>(in.model.state);
  for (int i = 0; i < 3; ++i) {
    out.anchor_m[i] = in.model.anchor_W_m[i];
    out.normal[i] = in.model.normal_W[i];
    out.feedforward_n[i] = in.model.feedforward_W_N[i];
    out.tool_force_n[i] = in.tool_force_W_N[i];
    out.drag_direction[i] = in.model.drag_direction_W[i];
    out.stick_m[i] = in.model.stick_W_m[i];
    out.tip_anchor_m[i] = in.model.tip_anchor_W_m[i];
  }
  out.tip_stiffness_n_per_m = in.model.tip_stiffness_N_per_m;
  out.stick_stiffness_n_per_m = in.model.stick_stiffness_N_per_m;
  out.drag_n = in.model.drag_N;
  out.drag_damping_ns_per_m = in.model.drag_damping_Ns_per_m;
  out.stiffness_n_per_m = in.model.stiffness_N_per_m;
  out.damping_ns_per_m = in.model.damping_Ns_per_m;
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
  void StartReceiving(Session* session) override {
    condition_ = owner_->io_.AttachReader(pose_reader_.handle(), reinterpret_cast<dds_attach_t>(session));
  }
  void StopReceiving() override { condition_.Reset(); }  // deleting the condition detaches it

  hapsim::dds::PoseReader& pose_reader() { return pose_reader_; }

 private:
  ServerDds* owner_;
  hapsim::dds::PoseReader pose_reader_;
  hapsim::dds::ModelWriter model_writer_;
  hapsim_dds_LocalForceModel wire_{};
  hapsim::dds::Entity condition_;
};

ServerDds::ServerDds(const hapsim::dds::Options& options, PoseLimits limits)
    : participant_(options), limits_(limits), io_(participant_) {}

ServerDds::~ServerDds() { Stop(); }

std::shared_ptr<SessionPort> ServerDds::Open(const std::string& session_id) {
  return std::make_shared<Port>(this, session_id);
}

void ServerDds::Start(SessionRegistry* registry, TickPool* pool) {
  registry_ = registry;
  pool_ = pool;
  // Every wake refreshes the table first: it holds the sessions it names
  // alive for the pass.
  io_.Start({[this] { RefreshIndex(); }, [this](dds_attach_t tag) { OnReader(tag); }});
}

void ServerDds::Stop() {
  io_.Stop();
  table_.reset();
  index_.clear();
}

void ServerDds::RefreshIndex() {
  auto table = registry_->Table();
  if (table == table_) return;
  table_ = std::move(table);
  index_.clear();
  for (const auto& [id, session] : *table_) index_.push_back(session.get());
  std::sort(index_.begin(), index_.end());
}

void ServerDds::OnReader(dds_attach_t tag) {
  auto* session = reinterpret_cast<Session*>(tag);
  // A tag is trusted only if the session is in the table we hold (a closing
  // session is removed from the table before its reader is detached, a new
  // one attached after it is published).
  if (!std::binary_search(index_.begin(), index_.end(), session)) return;
  RoutePoses(*session, static_cast<Port&>(session->port()));
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
