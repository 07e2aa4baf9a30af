#include "hapsim/gui/class_board.h"

#include <chrono>
#include <cstdio>

#include "hapsim/viewer/session_client.h"

namespace hapsim::gui {

ClassBoard::ClassBoard(viewer::Connection connection, std::string class_name, double rate_hz)
    : connection_(std::move(connection)), class_name_(std::move(class_name)), rate_hz_(rate_hz) {
  view_.class_name = class_name_;
  thread_ = std::thread([this] { Loop(); });
}

ClassBoard::~ClassBoard() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    if (context_) context_->TryCancel();
    wake_.notify_all();
  }
  thread_.join();
}

ClassView ClassBoard::View() const {
  std::lock_guard lock(mutex_);
  return view_;
}

void ClassBoard::Apply(const hapsim::v1::ClassStatus& status) {
  std::lock_guard lock(mutex_);
  view_.sessions.clear();
  for (const auto& s : status.sessions()) {
    SessionTile& tile = tiles_[s.session_id()];
    tile.status = s;
    for (const auto& e : s.events()) {
      char item[64];
      std::snprintf(item, sizeof item, "%s@%.2fs", e.kind().c_str(), e.t_s());
      tile.recent_events.push_back(item);
      if (tile.recent_events.size() > 4) tile.recent_events.pop_front();
    }
    tile.force_history_N.push_back(static_cast<float>(s.force_n()));
    if (tile.force_history_N.size() > kHistory) tile.force_history_N.pop_front();
    view_.sessions.push_back(tile);
  }
  view_.missing.assign(status.missing_sessions().begin(), status.missing_sessions().end());
  view_.updates = status.seq() + 1;
  view_.connection = "live";
}

void ClassBoard::Loop() {
  std::shared_ptr<grpc::Channel> channel;
  try {
    channel = viewer::MakeChannel(connection_);
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    view_.connection = std::string("cannot connect: ") + e.what();
    return;
  }
  auto stub = hapsim::v1::SessionService::NewStub(channel);
  while (!stop_) {
    grpc::ClientContext context;
    viewer::AddToken(&context, connection_.token);
    {
      std::lock_guard lock(mutex_);
      if (stop_) break;
      context_ = &context;
    }
    hapsim::v1::WatchClassRequest request;
    request.set_class_name(class_name_);
    request.set_rate_hz(rate_hz_);
    auto reader = stub->WatchClass(&context, request);
    hapsim::v1::ClassStatus status;
    while (reader->Read(&status)) Apply(status);
    const grpc::Status end = reader->Finish();
    std::unique_lock lock(mutex_);
    context_ = nullptr;
    if (stop_) break;
    view_.connection = "lost: " + viewer::DescribeStatus(end) + " — retrying";
    wake_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_.load(); });
  }
}

}  // namespace hapsim::gui
