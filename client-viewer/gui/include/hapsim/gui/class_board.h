// The instructor's class view, kept current from the WatchClass stream on
// a thread of its own (reconnecting like StreamWorker): the newest status of
// every session, plus per session its last events and a short history of
// |force| for the tile's sparkline.
#pragma once
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hapsim/v1/session.grpc.pb.h"
#include "hapsim/viewer/connection.h"

namespace hapsim::gui {

struct SessionTile {
  hapsim::v1::SessionStatus status;  // newest (its events: those of the newest update only)
  std::deque<std::string> recent_events;  // "puncture@4.03s", newest last, at most 4
  std::deque<float> force_history_N;      // newest last, at most kHistory
};

struct ClassView {
  std::string class_name;
  std::string connection = "connecting";
  std::uint64_t updates = 0;
  std::vector<SessionTile> sessions;     // sorted by id, as the server sends them
  std::vector<std::string> missing;      // sessions of the class not running
};

class ClassBoard {
 public:
  static constexpr std::size_t kHistory = 120;  // 12 s at 10 Hz

  ClassBoard(viewer::Connection connection, std::string class_name, double rate_hz);
  ~ClassBoard();
  ClassView View() const;

 private:
  void Loop();
  void Apply(const hapsim::v1::ClassStatus& status);

  viewer::Connection connection_;
  std::string class_name_;
  double rate_hz_;
  mutable std::mutex mutex_;
  ClassView view_;
  std::map<std::string, SessionTile> tiles_;
  std::atomic<bool> stop_{false};
  grpc::ClientContext* context_ = nullptr;  // guarded by mutex_
  std::condition_variable wake_;
  std::thread thread_;
};

}  // namespace hapsim::gui
