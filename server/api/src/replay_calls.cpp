#include "hapsim/api/replay_calls.h"

#include <cmath>

#include "hapsim/api/call_status.h"
#include "hapsim/api/session_service.h"
#include "hapsim/recording/replay.h"
#include "hapsim/runtime/scene_builder.h"

namespace hapsim::service {

ReplayCalls::ReplayCalls(SessionRegistry* registry, const RecordingCalls* recordings, const AccessPolicy* policy)
    : registry_(registry), recordings_(recordings), policy_(policy ? policy : &OpenAccessPolicy()) {}

void ReplayCalls::ForgetClosedLocked() {
  for (auto it = replays_.begin(); it != replays_.end();) {
    const auto session = registry_->Find(it->first);
    if (session && session->input_source() == it->second.player.get()) {
      ++it;
      continue;
    }
    policy_->RemoveReplay(it->first);
    it = replays_.erase(it);
  }
}

void ReplayCalls::Start(const std::string& id, const StoredRecording& recording, const std::string& recording_id,
                        double speed, bool paused, double start_s, std::shared_ptr<CheckpointStates> kept) {
  if (!(speed >= kMinSpeed && speed <= kMaxSpeed)) {
    throw ServiceError(ErrorCode::kInvalidArgument, "replay speed must be within [0.1, 10]");
  }
  if (!(start_s >= 0.0 && start_s <= 1e7)) throw ServiceError(ErrorCode::kInvalidArgument, "start must be >= 0 s");
  std::shared_ptr<RecordingPlayer> player;
  std::unique_ptr<core::Scene> scene;
  std::uint64_t rerun_ticks = 0;
  // Reading, checking and (to start later than the beginning) re-running the
  // trial to there: seconds for a long trial, so below the ticks' priority.
  RunAtLowPriority([&] {
    auto bytes = ReadRecordingBytes(recording.path);
    const RecordingHeader header = ReadRecordingHeader(bytes);
    const auto start_tick =
        header.first_tick + static_cast<std::uint64_t>(std::llround(start_s / header.tick_period_s));
    try {
      player = std::make_shared<RecordingPlayer>(std::move(bytes), start_tick);
    } catch (const std::invalid_argument& e) {
      throw ServiceError(ErrorCode::kInvalidArgument, std::string("no such moment in the trial: ") + e.what());
    }
    if (!kept) {
      kept = std::make_shared<CheckpointStates>(
          header.first_tick,
          CheckpointStates::SpacingFor(player->summary().ticks, CheckpointStates::kDefaultMaxStates, 1));
    }
    if (start_tick == header.first_tick) {
      scene = core::MakeScene({header.scene, header.params});
      return;
    }
    ReplayOptions options;
    options.until_tick = start_tick - 1;
    if (const auto nearest = kept->Nearest(start_tick)) options.from = {nearest->scene, nearest->next_tick};
    options.after_matched_checkpoint = [&](const RecordedCheckpoint& c, const core::Scene& at) {
      kept->Offer(c.tick + 1, at);
    };
    ReplayResult before = Replay(player->bytes(), options);
    if (!before.ok()) {
      throw ServiceError(
          ErrorCode::kFailedPrecondition,
          "the recording diverges from its own state hashes after tick " + std::to_string(before.mismatch->tick));
    }
    rerun_ticks = before.ticks_run;
    scene = std::move(before.scene);
  });
  const RecordingHeader& header = player->header();
  SessionSeed seed;
  seed.scene = std::move(scene);
  seed.paused = paused;
  seed.listener = player;
  seed.source = player;
  seed.tick_period_s = header.tick_period_s / speed;
  seed.step_s = header.tick_period_s;
  policy_->AddReplay(id, header.session_id);
  try {
    registry_->CreateSeeded(id, header.scene, header.owner, header.params, std::move(seed));
  } catch (...) {
    policy_->RemoveReplay(id);
    throw;
  }
  replays_[id] = Playing{recording_id, header.session_id, speed, std::move(player), std::move(kept), rerun_ticks};
}

std::pair<std::shared_ptr<Session>, ReplayCalls::Playing> ReplayCalls::FindReplay(const grpc::ServerContext* context,
                                                                                  const std::string& id,
                                                                                  Action action) {
  const auto who = AuthenticateCall(*policy_, context);
  std::lock_guard lock(mutex_);
  ForgetClosedLocked();
  const auto it = replays_.find(id);
  if (it == replays_.end()) throw ServiceError(ErrorCode::kNotFound, "no replay session '" + id.substr(0, 80) + "'");
  policy_->Authorize(who, action, id);
  return {registry_->FindOrThrow(id), it->second};
}

void ReplayCalls::Describe(const Session& session, const Playing& replay, hapsim::v1::ReplayInfo* out) const {
  DescribeSession(session, out->mutable_session());
  const auto& summary = replay.player->summary();
  const auto progress = replay.player->progress();
  const double period_s = summary.header.tick_period_s;
  out->set_recording_id(replay.recording_id);
  out->set_speed(replay.speed);
  out->set_trial_s(static_cast<double>(progress.next_tick - summary.header.first_tick) * period_s);
  out->set_trial_length_s(static_cast<double>(summary.ticks) * period_s);
  out->set_checkpoints(summary.checkpoints);
  out->set_checkpoints_matched(progress.checkpoints_matched);
  out->set_checkpoints_diverged(progress.checkpoints_diverged);
  out->set_ended(progress.ended);
  out->set_rerun_ticks(replay.rerun_ticks);
  out->set_kept_states(replay.kept->size());
}

grpc::Status ReplayCalls::OpenReplay(grpc::ServerContext* context, const hapsim::v1::OpenReplayRequest* req,
                                     hapsim::v1::ReplayInfo* out) {
  return Guarded("OpenReplay", [&] {
    const StoredRecording recording = recordings_->Find(context, req->recording_id(), Action::kView);
    std::string id;
    {
      std::lock_guard lock(mutex_);
      ForgetClosedLocked();
      if (replays_.size() >= kMaxReplays) {
        throw ServiceError(ErrorCode::kResourceExhausted,
                           "this server already plays " + std::to_string(kMaxReplays) + " replays: close one");
      }
      do {
        id = "replay-" + std::to_string(next_id_++);
      } while (registry_->Find(id));
      Start(id, recording, req->recording_id(), req->speed() == 0.0 ? 1.0 : req->speed(), req->paused(), req->start_s(),
            nullptr);
    }
    const auto [session, replay] = FindReplay(context, id, Action::kView);
    Describe(*session, replay, out);
  });
}

grpc::Status ReplayCalls::GetReplay(grpc::ServerContext* context, const hapsim::v1::SessionRef* req,
                                    hapsim::v1::ReplayInfo* out) {
  return Guarded("GetReplay", [&] {
    const auto [session, replay] = FindReplay(context, req->session_id(), Action::kView);
    Describe(*session, replay, out);
  });
}

grpc::Status ReplayCalls::StepReplay(grpc::ServerContext* context, const hapsim::v1::StepReplayRequest* req,
                                     hapsim::v1::ReplayInfo* out) {
  return Guarded("StepReplay", [&] {
    const auto [session, replay] = FindReplay(context, req->session_id(), Action::kControl);
    const std::uint32_t ticks = req->ticks() == 0 ? 1 : req->ticks();
    if (ticks > 100000) throw ServiceError(ErrorCode::kInvalidArgument, "step at most 100000 ticks at once");
    if (!session->paused()) {
      throw ServiceError(ErrorCode::kFailedPrecondition, "replay '" + req->session_id() + "' plays: pause it to step");
    }
    replay.player->RequestSteps(ticks);
    Describe(*session, replay, out);
  });
}

grpc::Status ReplayCalls::SeekReplay(grpc::ServerContext* context, const hapsim::v1::SeekReplayRequest* req,
                                     hapsim::v1::ReplayInfo* out) {
  return Guarded("SeekReplay", [&] {
    const auto [session, replay] = FindReplay(context, req->session_id(), Action::kControl);
    const StoredRecording recording = recordings_->Find(context, replay.recording_id, Action::kView);
    const bool paused = session->paused();
    {
      std::lock_guard lock(mutex_);
      registry_->Close(req->session_id());  // the same id goes on at the new moment
      replays_.erase(req->session_id());
      Start(req->session_id(), recording, replay.recording_id, replay.speed, paused, req->trial_s(), replay.kept);
    }
    const auto [again, now] = FindReplay(context, req->session_id(), Action::kView);
    Describe(*again, now, out);
  });
}

}  // namespace hapsim::service
