#include "hapsim/classroom/access_policy.h"

#include <algorithm>
#include <cctype>
#include <string_view>

#include "hapsim/runtime/errors.h"

namespace hapsim::service {

const char* ActionName(Action action) {
  switch (action) {
    case Action::kListScenes: return "list scenes";
    case Action::kListSessions: return "list sessions";
    case Action::kView: return "view";
    case Action::kJoin: return "join (drive)";
    case Action::kControl: return "pause/resume/reset";
    case Action::kCreateClose: return "create/close";
    case Action::kScore: return "score";
    case Action::kWatchClass: return "watch the class";
    case Action::kPushScenario: return "push a scenario to";
  }
  return "?";
}

AccessPolicy::AccessPolicy(ClassConfig config) : enabled_(true), config_(std::move(config)) {
  for (const auto& token : config_.tokens) by_hash_.emplace(token.sha256_hex, &token);
}

const ClassDef* AccessPolicy::FindClass(std::string_view name) const {
  for (const auto& c : config_.classes) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string AccessPolicy::TraineeOf(std::string_view session_id) const {
  const ClassDef* cls = ClassOf(session_id);
  return cls ? cls->Find(session_id)->trainee : std::string();
}

const ClassDef* AccessPolicy::ClassOf(std::string_view session_id) const {
  for (const auto& c : config_.classes) {
    if (c.Has(session_id)) return &c;
  }
  return nullptr;
}

std::optional<Principal> AccessPolicy::Authenticate(const std::string* authorization) const {
  if (!enabled_) return std::nullopt;
  auto refuse = [&](const std::string& why) {
    counters_.unauthenticated.fetch_add(1, std::memory_order_relaxed);
    return ServiceError(ErrorCode::kUnauthenticated, why);
  };
  if (!authorization) throw refuse("this server needs a token: send metadata 'authorization: Bearer TOKEN'");
  // "Bearer", any case (HTTP's auth schemes are case-insensitive, RFC 9110
  // 11.1), then one or more spaces, then the token.
  const std::string_view value(*authorization);
  constexpr std::string_view kScheme = "bearer";
  const bool scheme_ok = value.size() > kScheme.size() && value[kScheme.size()] == ' ' &&
                         std::equal(kScheme.begin(), kScheme.end(), value.begin(), [](char want, char got) {
                           return want == std::tolower(static_cast<unsigned char>(got));
                         });
  const std::size_t token_at = scheme_ok ? value.find_first_not_of(' ', kScheme.size()) : std::string_view::npos;
  if (value.size() > 4096 || token_at == std::string_view::npos) {
    throw refuse("malformed authorization metadata: expected 'Bearer TOKEN'");
  }
  const auto found = by_hash_.find(Sha256Hex(value.substr(token_at)));
  if (found == by_hash_.end()) throw refuse("unknown token");
  const TokenDef& t = *found->second;
  Principal p;
  p.name = t.name;
  p.role = t.role;
  p.class_name = t.class_name;
  p.sessions.insert(t.sessions.begin(), t.sessions.end());
  return p;
}

void AccessPolicy::AddReplay(const std::string& replay_id, const std::string& recorded_session_id) const {
  std::lock_guard lock(replays_mutex_);
  replays_[replay_id] = recorded_session_id;
}

void AccessPolicy::RemoveReplay(std::string_view replay_id) const {
  std::lock_guard lock(replays_mutex_);
  const auto it = replays_.find(replay_id);
  if (it != replays_.end()) replays_.erase(it);
}

std::string AccessPolicy::ReplayedSession(std::string_view target) const {
  std::lock_guard lock(replays_mutex_);
  const auto it = replays_.find(target);
  return it == replays_.end() ? std::string() : it->second;
}

bool AccessPolicy::Allows(const std::optional<Principal>& who, Action action, std::string_view target) const {
  if (!enabled_) return true;
  if (!who) return false;
  switch (action) {  // a replay: as its recorded session's viewers may see it
    case Action::kView:
    case Action::kControl:
    case Action::kCreateClose:
    case Action::kJoin:
      if (const std::string recorded = ReplayedSession(target); !recorded.empty()) {
        return action != Action::kJoin && Allows(who, Action::kView, recorded);
      }
      break;
    default:
      break;
  }
  const Role role = who->role;
  const ClassDef* own_class = FindClass(who->class_name);
  const bool in_class = own_class && own_class->Has(target);
  const bool own_session = who->sessions.count(target) > 0;
  switch (action) {
    case Action::kListScenes:
    case Action::kListSessions: return true;  // the list itself is filtered by kView
    case Action::kView: return role == Role::kTrainee ? own_session : in_class;
    case Action::kJoin: return role == Role::kTrainee ? own_session : role == Role::kInstructor && in_class;
    case Action::kControl:
    case Action::kCreateClose:
    case Action::kScore: return role == Role::kInstructor && in_class;
    case Action::kWatchClass: return role != Role::kTrainee && target == who->class_name;
    case Action::kPushScenario: return role == Role::kInstructor && target == who->class_name;
  }
  return false;
}

void AccessPolicy::Authorize(const std::optional<Principal>& who, Action action, std::string_view target) const {
  if (Allows(who, action, target)) return;
  if (!who) throw ServiceError(ErrorCode::kUnauthenticated, "this server needs a token");
  counters_.permission_denied.fetch_add(1, std::memory_order_relaxed);
  const std::string what = target.empty() ? "" : " '" + std::string(target.substr(0, 80)) + "'";
  throw ServiceError(ErrorCode::kPermissionDenied, who->name + " (" + RoleName(who->role) + " of class " +
                                                       who->class_name + ") may not " + ActionName(action) + what);
}

}  // namespace hapsim::service
