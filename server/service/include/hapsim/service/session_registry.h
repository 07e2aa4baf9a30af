// The server's sessions by id. Thread-safe; no real-time thread touches it
// (the DDS thread and frame pump take a snapshot of the list per pass).
#pragma once
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/service/errors.h"
#include "hapsim/service/session.h"

namespace hapsim::service {

struct SessionDefaults {
  double tick_period_s = 0.001;
  double frame_rate_hz = 60.0;
  double pose_timeout_s = 0.25;
  std::size_t max_sessions = 64;
};

// Session ids: 1 to 63 characters of [A-Za-z0-9_-] (they travel in a 64-byte
// DDS field and appear in logs and file names).
bool IsValidSessionId(std::string_view id);

class SessionRegistry {
 public:
  SessionRegistry(SessionDefaults defaults, std::function<void()> wake_dds);
  ~SessionRegistry();

  // Builds and starts a session. Throws ServiceError: kInvalidArgument (bad
  // id, unknown scene, bad parameter), kAlreadyExists, kResourceExhausted.
  // config.tick_period_s etc. are taken from the defaults.
  std::shared_ptr<Session> Create(std::string id, std::string scene, std::string owner,
                                  std::map<std::string, double> params);
  std::shared_ptr<Session> Find(std::string_view id) const;       // nullptr if none
  std::shared_ptr<Session> FindOrThrow(std::string_view id) const;  // kNotFound
  // Stops the session and ends its viewer streams. Throws kNotFound.
  void Close(std::string_view id);
  void CloseAll();
  std::vector<std::shared_ptr<Session>> List() const;  // sorted by id

 private:
  SessionDefaults defaults_;
  std::function<void()> wake_dds_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Session>, std::less<>> sessions_;
  std::uint64_t next_generated_id_ = 1;
};

}  // namespace hapsim::service
