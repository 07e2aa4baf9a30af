// The server's sessions by id.
//
// The real-time paths never wait for a control RPC: the DDS thread and the
// frame pump read the sessions through an immutable, copy-on-write table
// (Table(): one pointer copy), never through the mutex that Create/Close take.
// Create reserves the id under that mutex, builds the scene with no lock held
// (on a low-priority thread, so a slow build yields the CPU to ticks), then
// publishes a new table, lets poses reach the session (its port) and hands
// it to the tick pool. Close undoes these in reverse order, then tells the
// listener (the ViewerHub, which ends the session's viewer streams). The
// registry knows no wire format: bad requests are ServiceErrors.
#pragma once
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/common/shared_snapshot.h"
#include "hapsim/runtime/errors.h"
#include "hapsim/runtime/session.h"
#include "hapsim/runtime/tick_pool.h"

namespace hapsim::service {

struct SessionDefaults {
  double tick_period_s = 0.001;
  double frame_rate_hz = 60.0;
  double pose_timeout_s = 0.25;
  double pose_slack_s = 0.0005;
  double pose_extrapolation_s = 0.1;
  ModelDeadbandConfig model_deadband;
  std::size_t max_sessions = 64;
};

// An immutable view of the sessions at one instant, sorted by id.
using SessionTable = std::map<std::string, std::shared_ptr<Session>, std::less<>>;

enum class CloseReason { kClosed, kServerStopping };

// Makes what follows a new session's ticks (may return nullptr).
using TickListenerFactory = std::function<std::shared_ptr<TickListener>(const SessionConfig&)>;

// How a session starts when not fresh: brought back after a server restart
// (its scene as its recording left it, going on from first_tick), or as a
// replay of a recording (its inputs from a source, at a chosen speed).
struct SessionSeed {
  std::unique_ptr<core::Scene> scene;  // nullptr: build a fresh one
  std::uint64_t first_tick = 0;
  bool paused = false;
  std::shared_ptr<TickListener> listener;   // set: this one, not the registry's factory's
  std::shared_ptr<TickInputSource> source;  // set: inputs from it, not from a device
  double tick_period_s = 0.0;               // > 0: instead of the server's (a replay's speed)
  double step_s = 0.0;                      // > 0: sim time per tick, when not the tick period
};

// Told when a session has stopped (no tick runs, no pose arrives any more).
class SessionListener {
 public:
  virtual ~SessionListener() = default;
  virtual void OnSessionClosed(Session& session, CloseReason why) = 0;
};

class SessionRegistry {
 public:
  // pool runs the ticks; transport opens each session's port (its DDS
  // partition's endpoints); listener (may be null) hears of every close;
  // tick_listeners (may be empty) gives each new session its TickListener.
  SessionRegistry(SessionDefaults defaults, TickPool* pool, SessionTransport* transport,
                  SessionListener* listener = nullptr, TickListenerFactory tick_listeners = {});
  ~SessionRegistry();

  // Builds a session and starts its ticks. Throws ServiceError:
  // kInvalidArgument (bad id, unknown scene, bad parameter), kAlreadyExists
  // (also while a session of that id is being built), kResourceExhausted.
  std::shared_ptr<Session> Create(std::string id, std::string scene, std::string owner,
                                  std::map<std::string, double> params);
  // As Create, for a session that does not start fresh: brought back after a
  // server restart, or a replay of a recording (SessionSeed).
  std::shared_ptr<Session> CreateSeeded(std::string id, std::string scene_name, std::string owner,
                                        std::map<std::string, double> params, SessionSeed seed);
  std::shared_ptr<Session> Find(std::string_view id) const;       // nullptr if none
  std::shared_ptr<Session> FindOrThrow(std::string_view id) const;  // kNotFound
  // Stops the session's ticks and poses, then tells the listener. Throws kNotFound.
  void Close(std::string_view id);
  void CloseAll();
  std::vector<std::shared_ptr<Session>> List() const;  // sorted by id
  // Lock-free read for the real-time paths.
  std::shared_ptr<const SessionTable> Table() const { return table_.Load(); }

 private:
  // Create's three steps: reserve the id (brief lock; a generated one if
  // empty), build the session with no lock held, publish it in the table.
  std::string Reserve(std::string id, const std::string& owner);
  std::shared_ptr<Session> Build(const std::string& id, std::string scene, std::string owner,
                                 std::map<std::string, double> params, SessionSeed seed);
  void Publish(const std::string& id, const std::shared_ptr<Session>& session);
  void PublishTableLocked();
  void Shut(Session& session, CloseReason why);
  void ReleaseReservation(const std::string& id);  // a build failed

  SessionDefaults defaults_;
  TickPool* pool_;
  SessionTransport* transport_;
  SessionListener* listener_;
  TickListenerFactory tick_listeners_;
  std::mutex mutex_;  // guards sessions_, reserved_, next_generated_id_; never taken by a tick or the DDS thread
  SessionTable sessions_;
  std::set<std::string, std::less<>> reserved_;  // ids being built
  std::uint64_t next_generated_id_ = 1;
  common::SharedSnapshot<SessionTable> table_{std::make_shared<const SessionTable>()};
};

}  // namespace hapsim::service
