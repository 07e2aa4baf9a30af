#include "hapsim/service/server_dds.h"

#include <array>

#include <spdlog/spdlog.h>

#include "hapsim/runtime/clock.h"

namespace hapsim::service {

namespace {
constexpr const char* kPoseTopic = "hapsim_StylusPose";
constexpr const char* kModelTopic = "hapsim_LocalForceModel";
constexpr std::int64_t kWaitTimeoutNs = 5'000'000;       // wake at least every 5 ms
constexpr std::int64_t kWarningIntervalNs = 2'000'000'000;  // rate-limit bad-input warnings
}  // namespace

ServerDds::ServerDds(const runtime::DdsOptions& options, PoseLimits limits)
    : participant_(options),
      pose_reader_(participant_, &hapsim_dds_StylusPose_desc, kPoseTopic),
      model_writer_(participant_, &hapsim_dds_LocalForceModel_desc, kModelTopic),
      waitset_(participant_),
      limits_(limits) {
  waitset_.AttachReader(pose_reader_.handle());
}

ServerDds::~ServerDds() { Stop(); }

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
}

void ServerDds::Run() {
  while (!stop_.load()) {
    waitset_.Wait(kWaitTimeoutNs);
    RoutePoses();
  }
}

void ServerDds::RoutePoses() {
  std::array<hapsim_dds_StylusPose, 64> batch;
  for (;;) {
    const std::size_t n = pose_reader_.Take(batch);
    if (n == 0) return;
    const std::int64_t now = runtime::SteadyNowNs();
    const auto table = registry_->Table();  // copy-on-write: no lock shared with control RPCs
    for (std::size_t i = 0; i < n; ++i) {
      const auto& sample = batch[i];
      PoseRejection why = PoseRejection::kNone;
      const auto tool = FilterPose(sample, limits_, &why);
      const std::string_view sid = SessionIdOf(sample.session);
      const auto found = sid.empty() ? table->end() : table->find(sid);
      Session* session = found == table->end() ? nullptr : found->second.get();
      if (!tool) {
        counters_.poses_rejected.fetch_add(1);
        if (session) session->counters().poses_rejected.fetch_add(1);
        if (now - last_warning_ns_ > kWarningIntervalNs) {
          last_warning_ns_ = now;
          spdlog::warn("dropped a pose from device {} (session '{}'): {}", sample.device_id, sid, ToString(why));
        }
        continue;
      }
      if (!session) {
        counters_.poses_unknown_session.fetch_add(1);
        if (now - last_warning_ns_ > kWarningIntervalNs) {
          last_warning_ns_ = now;
          spdlog::warn("pose from device {} for unknown session '{}' ignored", sample.device_id, sid);
        }
        continue;
      }
      if (!session->OfferPose(PoseSample{*tool, sample.device_id, sample.seq, now})) {
        counters_.poses_other_device.fetch_add(1);
        if (now - last_warning_ns_ > kWarningIntervalNs) {
          last_warning_ns_ = now;
          spdlog::warn("pose from device {} for session '{}' dropped: device {} drives it", sample.device_id, sid,
                       session->counters().owning_device_id.load());
        }
        continue;
      }
      counters_.poses_accepted.fetch_add(1);
      pool_->Wake(session, session->PoseDueNs(now));
    }
    if (n < batch.size()) return;
  }
}

bool ServerDds::WriteForceModel(const hapsim_dds_LocalForceModel& model) {
  if (model_writer_.Write(model)) {
    counters_.force_models_written.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  counters_.write_failures.fetch_add(1, std::memory_order_relaxed);
  return false;
}

}  // namespace hapsim::service
