#include "hapsim/service/server_dds.h"

#include <algorithm>
#include <array>

#include <spdlog/spdlog.h>

#include "hapsim/runtime/clock.h"

namespace hapsim::service {

namespace {
constexpr const char* kPoseTopic = "hapsim_StylusPose";
constexpr const char* kModelTopic = "hapsim_LocalForceModel";
constexpr std::int64_t kWaitTimeoutNs = 5'000'000;          // wake at least every 5 ms
constexpr std::int64_t kWarningIntervalNs = 2'000'000'000;  // rate-limit bad-input warnings
}  // namespace

// One session's endpoints in its partition.
class ServerDds::Port : public SessionPort {
 public:
  Port(ServerDds* owner, const std::string& session_id)
      : owner_(owner),
        pose_reader_(owner->participant_, &hapsim_dds_StylusPose_desc, kPoseTopic, runtime::SessionPartition(session_id)),
        model_writer_(owner->participant_, &hapsim_dds_LocalForceModel_desc, kModelTopic,
                      runtime::SessionPartition(session_id)) {}

  bool WriteForceModel(const hapsim_dds_LocalForceModel& model) override {
    if (model_writer_.Write(model)) {
      owner_->counters_.force_models_written.fetch_add(1, std::memory_order_relaxed);
      return true;
    }
    owner_->counters_.write_failures.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  void StartReceiving(Session* session) override {
    condition_ = owner_->waitset_.AttachReader(pose_reader_.handle(), reinterpret_cast<dds_attach_t>(session));
  }
  void StopReceiving() override { condition_.Reset(); }  // deleting the condition detaches it

  runtime::DdsReader<hapsim_dds_StylusPose>& pose_reader() { return pose_reader_; }

 private:
  ServerDds* owner_;
  runtime::DdsReader<hapsim_dds_StylusPose> pose_reader_;
  runtime::DdsWriter<hapsim_dds_LocalForceModel> model_writer_;
  runtime::DdsEntity condition_;
};

ServerDds::ServerDds(const runtime::DdsOptions& options, PoseLimits limits)
    : participant_(options), waitset_(participant_), limits_(limits) {}

ServerDds::~ServerDds() { Stop(); }

std::shared_ptr<SessionPort> ServerDds::Open(const std::string& session_id) {
  return std::make_shared<Port>(this, session_id);
}

void ServerDds::Start(SessionRegistry* registry, TickPool* pool) {
  registry_ = registry;
  pool_ = pool;
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
}

void ServerDds::Stop() {
  stop_ = true;
  waitset_.Wake();
  if (thread_.joinable()) thread_.join();
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

void ServerDds::Run() {
  std::array<dds_attach_t, 64> tags;
  while (!stop_.load()) {
    const std::size_t n = waitset_.Wait(kWaitTimeoutNs, tags);
    RefreshIndex();  // holds the table: the sessions it names stay alive this pass
    for (std::size_t i = 0; i < n; ++i) {
      if (tags[i] == runtime::DdsWaitSet::kGuardTag) continue;
      auto* session = reinterpret_cast<Session*>(tags[i]);
      // A tag is trusted only if the session is in the table we hold (a
      // closing session is removed from the table before its reader is
      // detached, a new one attached after it is published).
      if (!std::binary_search(index_.begin(), index_.end(), session)) continue;
      RoutePoses(*session, static_cast<Port&>(session->port()));
    }
  }
}

bool ServerDds::WarningDue(std::int64_t now_ns) {
  if (now_ns - last_warning_ns_ <= kWarningIntervalNs) return false;
  last_warning_ns_ = now_ns;
  return true;
}

void ServerDds::RoutePoses(Session& session, Port& port) {
  std::array<hapsim_dds_StylusPose, 64> batch;
  for (;;) {
    const std::size_t n = port.pose_reader().Take(batch);
    if (n == 0) return;
    const std::int64_t now = runtime::SteadyNowNs();
    bool offered = false;
    for (std::size_t i = 0; i < n; ++i) {
      const auto& sample = batch[i];
      PoseRejection why = PoseRejection::kNone;
      const auto tool = FilterPose(sample, limits_, &why);
      if (!tool) {
        counters_.poses_rejected.fetch_add(1);
        session.counters().poses_rejected.fetch_add(1);
        if (WarningDue(now)) {
          spdlog::warn("dropped a pose from device {} (session '{}'): {}", sample.device_id, session.id(),
                       ToString(why));
        }
        continue;
      }
      if (SessionIdOf(sample.session) != session.id()) {
        counters_.poses_wrong_session.fetch_add(1);
        session.counters().poses_wrong_session.fetch_add(1);
        if (WarningDue(now)) {
          spdlog::warn("pose from device {} naming session '{}' arrived in the partition of session '{}': dropped",
                       sample.device_id, SessionIdOf(sample.session), session.id());
        }
        continue;
      }
      if (!session.OfferPose(PoseSample{*tool, sample.device_id, sample.seq, now})) {
        counters_.poses_other_device.fetch_add(1);
        if (WarningDue(now)) {
          spdlog::warn("pose from device {} for session '{}' dropped: device {} drives it", sample.device_id,
                       session.id(), session.counters().owning_device_id.load());
        }
        continue;
      }
      counters_.poses_accepted.fetch_add(1);
      offered = true;
    }
    if (offered) pool_->Wake(&session, session.PoseDueNs(now));
    if (n < batch.size()) return;
  }
}

}  // namespace hapsim::service
