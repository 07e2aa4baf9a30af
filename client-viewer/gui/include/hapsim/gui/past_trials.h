// The class console's past trials: the class's recorded trials as the
// server lists them (ListRecordings), one of them opened as a replay
// session (OpenReplay) that the console watches like a live trainee, and
// that replay driven: play/pause, step, seek, close. Every call runs on a
// thread of its own, one at a time in the order asked, so drawing never
// waits on the server; Snapshot() gives the newest answers.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/connection.h"

namespace hapsim::gui {

class PastTrials {
 public:
  // class_name: the console's class (only its trials are listed).
  PastTrials(viewer::Connection connection, std::string class_name);
  ~PastTrials();  // closes the replay it opened

  // Each queues one call (or, while one of the same kind is queued, nothing).
  void Refresh();
  // recording_id: a RecordingInfo id, or "latest" for the class's newest ended trial.
  void Open(const std::string& recording_id);
  void SetPaused(bool paused);
  void Step(std::uint32_t ticks);
  void Seek(double trial_s);
  void PollReplay();  // GetReplay: the open replay's progress
  void Close();       // the open replay's session

  struct View {
    std::vector<hapsim::v1::RecordingInfo> trials;  // the class's, newest first
    bool listed = false;
    std::optional<hapsim::v1::ReplayInfo> replay;  // the replay open now, as last heard
    std::uint64_t opened = 0;                      // replays opened so far (a new one: watch it)
    std::string last_result;                       // the last call's answer or error
    bool busy = false;                             // a call is on its way
  };
  View Snapshot() const;

 private:
  using Stub = hapsim::v1::SessionService::Stub;
  using Call = std::function<void(Stub&)>;
  // A call on the open replay: given a context with the token and deadline, and the replay's id.
  using ReplayCall = std::function<void(Stub&, grpc::ClientContext&, const std::string& replay_id)>;
  void Post(std::string kind, Call call);
  void PostOnReplay(std::string kind, ReplayCall call);
  void Loop();
  std::string ReplayId() const;  // "" when none is open
  void Answer(const grpc::Status& status, const std::string& what);
  void ApplyReplay(const grpc::Status& status, const hapsim::v1::ReplayInfo& info, const std::string& what);
  void PrepareContext(grpc::ClientContext* context) const;

  viewer::Connection connection_;
  std::string class_name_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<std::string, Call>> queue_;  // (kind, call)
  bool stop_ = false;
  View view_;
  std::thread thread_;
};

}  // namespace hapsim::gui
