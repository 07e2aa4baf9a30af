// Who may do what: the roles of the class config applied to every RPC.
// Authentication (token -> principal) and authorisation (principal x action
// x session) both live here, so the gRPC handlers ask one object and the
// role matrix is tested without a network (tests/service/access_policy_test).
//
//   action          instructor          trainee          observer
//   list scenes     yes                 yes              yes
//   list sessions   its class's         its own          its class's
//   view            class sessions      own sessions     class sessions   (GetSession, GetSnapshot, Subscribe,
//   GetScores) join (device)   class sessions      own sessions     no control         class sessions      no no
//   (pause, resume, reset) create / close  class sessions      no               no score           class sessions no no
//   watch class     its class           no               its class        (WatchClass, GetTrials)
//   push scenario   its class           no               no
//
// A replay of a recorded trial is a session of its own (hapsim-replay-N),
// registered here as a replay of the recorded session: who may view the
// recorded session may view the replay and drive it (pause, step, seek,
// close) — a trainee debriefs their own trial — and nobody joins it.
//
// Without a class config (development mode) every caller may do everything;
// the server then listens on loopback unless told otherwise, and warns
// loudly if told otherwise.
#pragma once
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "hapsim/classroom/class_config.h"

namespace hapsim::service {

enum class Action { kListScenes, kListSessions, kView, kJoin, kControl, kCreateClose, kScore, kWatchClass, kPushScenario };
const char* ActionName(Action action);

struct Principal {
  std::string name;
  Role role = Role::kObserver;
  std::string class_name;
  std::set<std::string, std::less<>> sessions;  // trainee: its own sessions
};

// Refused calls, for /metrics (hapsim_auth_failures_total).
struct AuthCounters {
  std::atomic<std::uint64_t> unauthenticated{0};
  std::atomic<std::uint64_t> permission_denied{0};
};

class AccessPolicy {
 public:
  AccessPolicy() = default;  // development mode: no tokens, everything allowed
  explicit AccessPolicy(ClassConfig config);

  bool enabled() const { return enabled_; }
  const ClassConfig& config() const { return config_; }
  const ClassDef* FindClass(std::string_view name) const;
  const ClassDef* ClassOf(std::string_view session_id) const;  // nullptr: in no class
  std::string TraineeOf(std::string_view session_id) const;    // "" for a session in no class

  // The caller behind an "authorization" metadata value ("Bearer TOKEN";
  // nullptr: none sent). Development mode: nullopt (anyone). Throws
  // ServiceError(kUnauthenticated) for a missing, malformed or unknown token.
  std::optional<Principal> Authenticate(const std::string* authorization) const;

  // Throws ServiceError(kPermissionDenied) unless `who` (nullopt: development
  // mode) may do `action` on `session_id` (empty for kListScenes,
  // kListSessions; the class name for kWatchClass and kPushScenario).
  void Authorize(const std::optional<Principal>& who, Action action, std::string_view target) const;
  bool Allows(const std::optional<Principal>& who, Action action, std::string_view target) const;

  AuthCounters& counters() const { return counters_; }

  // Replay sessions (any thread): `replay_id` replays `recorded_session_id`.
  // Const: registering a replay changes no rule, only which sessions exist.
  void AddReplay(const std::string& replay_id, const std::string& recorded_session_id) const;
  void RemoveReplay(std::string_view replay_id) const;

 private:
  // The recorded session `target` replays ("" if it is no replay).
  std::string ReplayedSession(std::string_view target) const;
  bool enabled_ = false;
  ClassConfig config_;
  std::map<std::string, const TokenDef*, std::less<>> by_hash_;
  mutable AuthCounters counters_;
  mutable std::mutex replays_mutex_;
  mutable std::map<std::string, std::string, std::less<>> replays_;  // replay session id -> recorded session id
};

}  // namespace hapsim::service
