// Replays of recorded trials as sessions (docs/recording.md, "Replay in the
// server"): OpenReplay makes a session "replay-N" whose ticks take the
// recording's inputs (a RecordingPlayer) at a chosen speed; viewers
// subscribe to it like to a live session, PauseSession/ResumeSession/
// ResetSession/CloseSession drive it, StepReplay plays single ticks while
// paused, SeekReplay goes to another moment: it restores the nearest state
// kept at a checkpoint earlier re-runs passed (CheckpointStates) and re-runs
// the trial only from there (off the tick, at low priority). Access: as the
// recorded session.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "hapsim/api/recording_calls.h"
#include "hapsim/recording/checkpoint_states.h"
#include "hapsim/recording/recording_player.h"
#include "hapsim/runtime/session_registry.h"

namespace hapsim::service {

class ReplayCalls {
 public:
  ReplayCalls(SessionRegistry* registry, const RecordingCalls* recordings, const AccessPolicy* policy);

  grpc::Status OpenReplay(grpc::ServerContext*, const hapsim::v1::OpenReplayRequest*, hapsim::v1::ReplayInfo*);
  grpc::Status GetReplay(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::ReplayInfo*);
  grpc::Status StepReplay(grpc::ServerContext*, const hapsim::v1::StepReplayRequest*, hapsim::v1::ReplayInfo*);
  grpc::Status SeekReplay(grpc::ServerContext*, const hapsim::v1::SeekReplayRequest*, hapsim::v1::ReplayInfo*);

  static constexpr std::size_t kMaxReplays = 16;  // open at once: each holds its file and a scene
  static constexpr double kMinSpeed = 0.1, kMaxSpeed = 10.0;

 private:
  struct Playing {
    std::string recording_id;
    std::string recorded_session_id;
    double speed = 1.0;
    std::shared_ptr<RecordingPlayer> player;
    std::shared_ptr<CheckpointStates> kept;  // kept across the replay's seeks
    std::uint64_t rerun_ticks = 0;           // re-run to reach where the last open or seek started
  };
  // Builds the session `id` playing the recording from `start_s` into the
  // trial, from the nearest of the `kept` states (null: a new replay).
  void Start(const std::string& id, const StoredRecording& recording, const std::string& recording_id, double speed,
             bool paused, double start_s, std::shared_ptr<CheckpointStates> kept);
  // The replay session `id` (throws kNotFound), after checking `action` on it.
  std::pair<std::shared_ptr<Session>, Playing> FindReplay(const grpc::ServerContext* context, const std::string& id,
                                                          Action action);
  void Describe(const Session& session, const Playing& replay, hapsim::v1::ReplayInfo* out) const;
  void ForgetClosedLocked();

  SessionRegistry* registry_;
  const RecordingCalls* recordings_;
  const AccessPolicy* policy_;
  std::mutex mutex_;  // guards replays_, next_id_
  std::map<std::string, Playing> replays_;
  std::uint64_t next_id_ = 1;
};

}  // namespace hapsim::service
