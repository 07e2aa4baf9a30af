#include "hapsim/gui/past_trials.h"

#include <algorithm>
#include <chrono>

#include "hapsim/viewer/session_client.h"

namespace hapsim::gui {

namespace {
constexpr double kCallTimeout_s = 30.0;  // a seek far into a long trial re-runs it: seconds
}

PastTrials::PastTrials(viewer::Connection connection, std::string class_name)
    : connection_(std::move(connection)), class_name_(std::move(class_name)) {
  thread_ = std::thread([this] { Loop(); });
}

PastTrials::~PastTrials() {
  Close();
  {
    std::lock_guard lock(mutex_);
    // Only the close still goes out: nothing else asked matters once the console is gone.
    std::erase_if(queue_, [](const auto& queued) { return queued.first != "close"; });
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

PastTrials::View PastTrials::Snapshot() const {
  std::lock_guard lock(mutex_);
  View view = view_;
  view.busy = view.busy || !queue_.empty();
  return view;
}

std::string PastTrials::ReplayId() const {
  std::lock_guard lock(mutex_);
  return view_.replay ? view_.replay->session().session_id() : "";
}

void PastTrials::Post(std::string kind, Call call) {
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    for (const auto& queued : queue_) {
      if (queued.first == kind) return;  // one of a kind waiting at a time: a held button does not pile calls up
    }
    queue_.emplace_back(std::move(kind), std::move(call));
  }
  wake_.notify_all();
}

void PastTrials::PrepareContext(grpc::ClientContext* context) const {
  viewer::AddToken(context, connection_.token);
  context->set_deadline(std::chrono::system_clock::now() +
                        std::chrono::milliseconds(static_cast<int>(kCallTimeout_s * 1e3)));
}

void PastTrials::Answer(const grpc::Status& status, const std::string& what) {
  std::lock_guard lock(mutex_);
  view_.last_result = status.ok() ? what + ": ok" : what + ": " + viewer::DescribeStatus(status);
}

void PastTrials::ApplyReplay(const grpc::Status& status, const hapsim::v1::ReplayInfo& info, const std::string& what) {
  {
    std::lock_guard lock(mutex_);
    if (status.ok()) view_.replay = info;
  }
  Answer(status, what);
}

void PastTrials::Loop() {
  std::unique_ptr<hapsim::v1::SessionService::Stub> stub;
  std::string init_error;
  try {
    stub = hapsim::v1::SessionService::NewStub(viewer::MakeChannel(connection_));
  } catch (const std::exception& e) {
    init_error = e.what();
  }
  while (true) {
    std::pair<std::string, Call> next;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopped, and everything asked was sent
      next = std::move(queue_.front());
      queue_.pop_front();
      view_.busy = true;
    }
    if (stub) {
      next.second(*stub);
    } else {
      std::lock_guard lock(mutex_);
      view_.last_result = "cannot connect: " + init_error;
    }
    std::lock_guard lock(mutex_);
    view_.busy = false;
  }
}

void PastTrials::Refresh() {
  Post("list", [this](hapsim::v1::SessionService::Stub& stub) {
    grpc::ClientContext context;
    PrepareContext(&context);
    hapsim::v1::RecordingList list;
    const grpc::Status status = stub.ListRecordings(&context, hapsim::v1::RecordingQuery(), &list);
    if (status.ok()) {
      std::vector<hapsim::v1::RecordingInfo> trials;
      for (const auto& r : list.recordings()) {
        if (class_name_.empty() || r.class_name() == class_name_) trials.push_back(r);
      }
      std::stable_sort(trials.begin(), trials.end(),
                       [](const auto& a, const auto& b) { return a.started_unix_ms() > b.started_unix_ms(); });
      std::lock_guard lock(mutex_);
      view_.trials = std::move(trials);
      view_.listed = true;
    }
    Answer(status, "list past trials");
  });
}

void PastTrials::Open(const std::string& recording_id) {
  Post("open", [this, recording_id](hapsim::v1::SessionService::Stub& stub) {
    std::string id = recording_id;
    if (id == "latest") {
      std::lock_guard lock(mutex_);
      id.clear();
      for (const auto& r : view_.trials) {  // newest first
        if (r.status() != "open") {
          id = r.id();
          break;
        }
      }
      if (id.empty()) {
        view_.last_result = "open the latest trial: the class has no ended trial yet";
        return;
      }
    }
    const std::string previous = ReplayId();
    if (!previous.empty()) {  // one replay at a time per console: the server holds at most 16
      grpc::ClientContext context;
      PrepareContext(&context);
      hapsim::v1::SessionRef ref;
      ref.set_session_id(previous);
      hapsim::v1::CloseSessionResponse closed;
      stub.CloseSession(&context, ref, &closed);
    }
    grpc::ClientContext context;
    PrepareContext(&context);
    hapsim::v1::OpenReplayRequest request;
    request.set_recording_id(id);
    hapsim::v1::ReplayInfo info;
    const grpc::Status status = stub.OpenReplay(&context, request, &info);
    if (status.ok()) {
      std::lock_guard lock(mutex_);
      ++view_.opened;
    } else {
      std::lock_guard lock(mutex_);
      view_.replay.reset();
    }
    ApplyReplay(status, info, "open " + id);
  });
}

void PastTrials::PostOnReplay(std::string kind, ReplayCall call) {
  Post(std::move(kind), [this, call = std::move(call)](hapsim::v1::SessionService::Stub& stub) {
    const std::string id = ReplayId();
    if (id.empty()) return;  // closed before the call's turn came
    grpc::ClientContext context;
    PrepareContext(&context);
    call(stub, context, id);
  });
}

void PastTrials::SetPaused(bool paused) {
  PostOnReplay("pause", [this, paused](Stub& stub, grpc::ClientContext& context, const std::string& id) {
    hapsim::v1::SessionRef ref;
    ref.set_session_id(id);
    hapsim::v1::SessionInfo info;
    const grpc::Status status =
        paused ? stub.PauseSession(&context, ref, &info) : stub.ResumeSession(&context, ref, &info);
    if (status.ok()) {
      std::lock_guard lock(mutex_);
      if (view_.replay) *view_.replay->mutable_session() = info;
    }
    Answer(status, std::string(paused ? "pause " : "play ") + id);
  });
}

void PastTrials::Step(std::uint32_t ticks) {
  PostOnReplay("step", [this, ticks](Stub& stub, grpc::ClientContext& context, const std::string& id) {
    hapsim::v1::StepReplayRequest request;
    request.set_session_id(id);
    request.set_ticks(ticks);
    hapsim::v1::ReplayInfo info;
    ApplyReplay(stub.StepReplay(&context, request, &info), info, "step " + id);
  });
}

void PastTrials::Seek(double trial_s) {
  PostOnReplay("seek", [this, trial_s](Stub& stub, grpc::ClientContext& context, const std::string& id) {
    hapsim::v1::SeekReplayRequest request;
    request.set_session_id(id);
    request.set_trial_s(trial_s);
    hapsim::v1::ReplayInfo info;
    ApplyReplay(stub.SeekReplay(&context, request, &info), info, "seek " + id);
  });
}

void PastTrials::PollReplay() {
  PostOnReplay("poll", [this](Stub& stub, grpc::ClientContext& context, const std::string& id) {
    hapsim::v1::SessionRef ref;
    ref.set_session_id(id);
    hapsim::v1::ReplayInfo info;
    const grpc::Status status = stub.GetReplay(&context, ref, &info);
    std::lock_guard lock(mutex_);
    if (status.ok()) {
      view_.replay = info;
    } else if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
      view_.replay.reset();  // closed elsewhere
    }
  });
}

void PastTrials::Close() {
  PostOnReplay("close", [this](Stub& stub, grpc::ClientContext& context, const std::string& id) {
    hapsim::v1::SessionRef ref;
    ref.set_session_id(id);
    hapsim::v1::CloseSessionResponse closed;
    const grpc::Status status = stub.CloseSession(&context, ref, &closed);
    {
      std::lock_guard lock(mutex_);
      view_.replay.reset();
    }
    Answer(status, "close " + id);
  });
}

}  // namespace hapsim::gui
