#include "hapsim/app/persistence.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <random>

#include "hapsim/recording/replay.h"

namespace hapsim::service {

namespace {

// A readable, time-sortable id for one incarnation of a session: its UTC
// creation time and a random suffix ("20261126T160512-3fa9").
std::string NewRunId() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[40];
  std::strftime(text, sizeof text, "%Y%m%dT%H%M%S", &utc);
  static thread_local std::mt19937 random{std::random_device{}()};
  char suffix[8];
  std::snprintf(suffix, sizeof suffix, "-%04x", static_cast<unsigned>(random() & 0xFFFFu));
  return std::string(text) + suffix;
}

// The listener that feeds a restored session's trial metrics during the
// replay: the reset that began the recorded trial already ended the one
// before it, so it is not counted again.
struct TrialFeed {
  SessionTrials* trials;
  std::uint64_t trial_first_tick;
  void operator()(const TickInput& in, const core::Scene& scene) const {
    TickInput input = in;
    if (in.tick == trial_first_tick) input.reset = false;
    const double force_N = scene.ToolForce_W_N().norm();
    trials->OnTick(TickOutcome{input, scene, scene.ForceModel().state, force_N});
  }
};

}  // namespace

bool ParseRecordPolicy(const std::string& text, RecordPolicy* out) {
  if (text == "none")
    *out = RecordPolicy::kNone;
  else if (text == "class")
    *out = RecordPolicy::kClass;
  else if (text == "all")
    *out = RecordPolicy::kAll;
  else
    return false;
  return true;
}

const char* RecordPolicyName(RecordPolicy policy) {
  switch (policy) {
    case RecordPolicy::kNone:
      return "none";
    case RecordPolicy::kClass:
      return "class";
    case RecordPolicy::kAll:
      return "all";
  }
  return "?";
}

Persistence::Persistence(PersistenceOptions options, const AccessPolicy* policy, SessionListener* next)
    : options_(std::move(options)), policy_(policy), next_(next) {
  namespace fs = std::filesystem;
  const fs::path dir(options_.data_dir);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error("cannot create data directory " + dir.string() + ": " + error.message());
  const std::string lock_path = (dir / "lock").string();
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0640);
  if (lock_fd_ < 0) throw std::runtime_error("cannot open " + lock_path + ": " + std::strerror(errno));
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    throw std::runtime_error("data directory " + dir.string() +
                             " is in use by another hapsim-server (one server per --data-dir)");
  }
  StoreOptions store_options;
  store_options.fsync_every_commit = options_.fsync_database;
  store_ = ResultsStore::Open((dir / "results.sqlite").string(), store_options);
  options_.recording.directory = (dir / "recordings").string();
  recording_ =
      std::make_unique<RecordingService>(options_.recording, [this](const RecordingEvent& e) { OnRecordingEvent(e); });
  spdlog::info("data directory {}: results database, recordings of {} sessions (flushed every {} ms{})", dir.string(),
               RecordPolicyName(options_.record), options_.recording.flush_interval_ms,
               options_.recording.fsync_interval_ms > 0
                   ? ", synced every " + std::to_string(options_.recording.fsync_interval_ms) + " ms"
                   : "");
}

Persistence::~Persistence() {
  Stop();
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void Persistence::Stop() {
  if (recording_) recording_->Stop();
  if (store_) store_->Flush();
}

bool Persistence::Recorded(const std::string& session_id) const {
  switch (options_.record) {
    case RecordPolicy::kNone:
      return false;
    case RecordPolicy::kClass:
      return policy_ && policy_->ClassOf(session_id) != nullptr;
    case RecordPolicy::kAll:
      return true;
  }
  return false;
}

TickListenerFactory Persistence::ListenerFactory() {
  return [this](const SessionConfig& config) { return ListenersFor(config); };
}

std::shared_ptr<TickListener> Persistence::ListenersFor(const SessionConfig& config) {
  const ClassDef* cls = policy_ ? policy_->ClassOf(config.id) : nullptr;
  StoredSession row;
  row.id = config.id;
  row.scene = config.scene;
  row.params = config.params;
  row.owner = config.owner;
  row.class_name = cls ? cls->name : "";
  row.run_id = NewRunId();
  row.created_unix_ms = UnixNowMs();
  {
    std::lock_guard lock(mutex_);
    sessions_[row.id] = row;
    run_of_[row.id] = row.run_id;
  }
  store_->UpsertSession(row);
  std::vector<std::shared_ptr<TickListener>> listeners;
  listeners.push_back(std::make_shared<SessionTrials>(cls ? cls->targets : TrialTargets{}));
  if (Recorded(config.id)) {
    listeners.push_back(recording_->Attach(
        RecordedSession{row.id, row.run_id, row.scene, row.params, row.owner, row.class_name, config.tick_period_s},
        config.first_tick));
  }
  return std::make_shared<TickListenerList>(std::move(listeners));
}

std::vector<std::string> Persistence::BringBack(SessionRegistry& registry, TrialBook& trials, ScoreBook& scores) {
  // What the last run left in the books: its trials (a running one whose
  // session does not come back was interrupted) and its score sheets.
  const std::vector<StoredSession> stored = store_->Sessions();
  std::map<std::string, std::string> live_runs;
  for (const auto& s : stored) live_runs[s.id] = s.run_id;
  std::vector<TrialRecord> earlier;
  for (StoredTrial& t : store_->Trials()) {
    if (t.record.end == "running") {
      const auto live = live_runs.find(t.record.session_id);
      if (live != live_runs.end() && live->second == t.run_id) continue;  // it runs on
      t.record.end = "interrupted";
      store_->UpsertTrial(t);
    }
    std::lock_guard lock(mutex_);
    if (!t.recording_path.empty()) trial_files_[{t.record.session_id, t.record.stats.trial}] = t.recording_path;
    earlier.push_back(std::move(t.record));
  }
  std::sort(earlier.begin(), earlier.end(), [](const TrialRecord& a, const TrialRecord& b) {
    return a.session_id != b.session_id ? a.session_id < b.session_id : a.stats.trial < b.stats.trial;
  });
  trials.Preload(std::move(earlier));
  std::size_t sheets = 0;
  for (const auto& sheet : store_->ScoreSheets()) {
    try {
      scores.Submit(sheet.session_id, sheet.scene, sheet.expert, sheet.indicators);
      ++sheets;
    } catch (const std::exception& e) {
      spdlog::warn("score sheet of '{}' for session '{}' not restored: {}", sheet.expert, sheet.session_id, e.what());
    }
  }
  scores.SetObserver(
      [this](const std::string& session_id, const std::string& scene, const std::string& expert,
             const std::vector<double>& indicators) { store_->SaveScoreSheet(session_id, scene, expert, indicators); });
  // A running trial's row at most 2 s behind (a recorded one is re-run exactly on restore anyway).
  trials.SetSink([this](const TrialRecord& record) { SinkTrial(record); }, 2.0);
  if (policy_) {
    const std::int64_t now_ms = UnixNowMs();
    for (const auto& cls : policy_->config().classes) {
      for (const auto& s : cls.sessions) store_->NoteRoster(cls.name, s.id, s.trainee, now_ms);
    }
  }
  // The sessions that were live.
  std::vector<std::string> back;
  for (const auto& s : stored) {
    if (RestoreOne(registry, s)) back.push_back(s.id);
  }
  spdlog::info("brought back {} of {} sessions, {} trials and {} score sheets from {}", back.size(), stored.size(),
               trials.Trials().size(), sheets, options_.data_dir);
  ApplyRetention();
  return back;
}

bool Persistence::RestoreOne(SessionRegistry& registry, const StoredSession& stored) {
  const auto started = std::chrono::steady_clock::now();
  try {
    const ClassDef* cls = policy_ ? policy_->ClassOf(stored.id) : nullptr;
    const TrialTargets targets = cls ? cls->targets : TrialTargets{};
    if (stored.recording_path.empty() || !std::filesystem::exists(stored.recording_path)) {
      // Not recorded: the same session, from its initial state (a new run).
      store_->RemoveSession(stored.id);
      registry.Create(stored.id, stored.scene, stored.owner, stored.params);
      spdlog::info("session '{}' brought back from its initial state (it was not recorded)", stored.id);
      return true;
    }
    const auto bytes = ReadRecordingBytes(stored.recording_path);
    const RecordingHeader header = ReadRecordingHeader(bytes);
    auto trials = std::make_shared<SessionTrials>(targets, header.trial);
    ReplayOptions options;
    options.after_tick = TrialFeed{trials.get(), header.first_tick};
    ReplayResult replay = Replay(bytes, options);
    const RecordingSummary& s = replay.summary;
    std::string refused;
    if (!replay.ok())
      refused = "its replay diverged from the recorded state after tick " + std::to_string(replay.mismatch->tick);
    else if (s.gap_at_tick)
      refused = "its recording lost inputs at tick " + std::to_string(*s.gap_at_tick);
    else if (s.ended)
      refused = "its recording was closed";
    else if (!replay.last_input)
      refused = "its recording holds no tick";
    if (!refused.empty()) {
      store_->RemoveSession(stored.id);
      registry.Create(stored.id, stored.scene, stored.owner, stored.params);
      spdlog::warn("session '{}' brought back from its initial state: {}", stored.id, refused);
      return true;
    }
    if (s.damage) spdlog::info("session '{}': recording read up to its torn end ({})", stored.id, s.damage->what());
    const std::uint64_t next_tick = s.next_tick();
    std::vector<std::shared_ptr<TickListener>> listeners{trials};
    if (Recorded(stored.id)) {
      listeners.push_back(recording_->Attach(RecordedSession{stored.id, stored.run_id, stored.scene, stored.params,
                                                             stored.owner, stored.class_name, header.tick_period_s},
                                             next_tick,
                                             RecordingResume{stored.recording_path, s.valid_bytes, header, next_tick}));
    }
    {
      std::lock_guard lock(mutex_);
      sessions_[stored.id] = stored;
      run_of_[stored.id] = stored.run_id;
      trial_files_[{stored.id, header.trial}] = stored.recording_path;
    }
    SessionSeed seed;
    seed.scene = std::move(replay.scene);
    seed.first_tick = next_tick;
    seed.paused = replay.last_input->paused;
    seed.listener = std::make_shared<TickListenerList>(std::move(listeners));
    registry.CreateSeeded(stored.id, stored.scene, stored.owner, stored.params, std::move(seed));
    const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    spdlog::info(
        "session '{}' brought back at tick {} (trial {}, {} checkpoints matched; {:.2f} s of trial re-run "
        "in {:.2f} s)",
        stored.id, next_tick, header.trial, replay.checkpoints_matched,
        static_cast<double>(replay.ticks_run) * header.tick_period_s, took_s);
    return true;
  } catch (const std::exception& e) {
    spdlog::error("session '{}' could not be brought back: {}", stored.id, e.what());
    store_->RemoveSession(stored.id);
    return false;
  }
}

void Persistence::OnSessionClosed(Session& session, CloseReason why) {
  if (why == CloseReason::kClosed) {
    store_->RemoveSession(session.id());
    std::lock_guard lock(mutex_);
    sessions_.erase(session.id());
  }
  if (next_) next_->OnSessionClosed(session, why);
}

void Persistence::OnRecordingEvent(const RecordingEvent& e) {
  StoredRecording r;
  r.path = e.path;
  r.session_id = e.session_id;
  r.run_id = e.run_id;
  r.trial = e.trial;
  r.trainee = e.owner;
  r.class_name = e.class_name;
  r.scene = e.scene;
  r.started_unix_ms = e.started_unix_ms;
  r.ticks = e.ticks;
  r.bytes = e.bytes;
  switch (e.kind) {
    case RecordingEvent::Kind::kOpened:
    case RecordingEvent::Kind::kProgress:
      r.status = "open";
      break;
    case RecordingEvent::Kind::kClosed:
      r.status = "closed";
      r.ended_unix_ms = e.ended_unix_ms;
      break;
    case RecordingEvent::Kind::kBroken:
      r.status = "broken";
      r.ended_unix_ms = UnixNowMs();
      break;
  }
  store_->UpsertRecording(r);
  if (e.kind != RecordingEvent::Kind::kOpened) return;
  StoredSession row;
  {
    std::lock_guard lock(mutex_);
    trial_files_[{e.session_id, e.trial}] = e.path;
    const auto it = sessions_.find(e.session_id);
    if (it == sessions_.end() || it->second.run_id != e.run_id) return;  // closed meanwhile
    it->second.recording_path = e.path;
    row = it->second;
  }
  store_->UpsertSession(row);  // a restart goes on from this trial's file
}

void Persistence::SinkTrial(const TrialRecord& record) {
  StoredTrial t;
  t.record = record;
  t.updated_unix_ms = UnixNowMs();
  {
    std::lock_guard lock(mutex_);
    const auto run = run_of_.find(record.session_id);
    if (run != run_of_.end()) t.run_id = run->second;
    const auto file = trial_files_.find({record.session_id, record.stats.trial});
    if (file != trial_files_.end()) t.recording_path = file->second;
  }
  const ClassDef* cls = policy_ ? policy_->ClassOf(record.session_id) : nullptr;
  t.class_name = cls ? cls->name : "";
  store_->UpsertTrial(t);
}

void Persistence::MaybeApplyRetention() {
  if (UnixNowMs() - last_retention_ms_ < 3600 * 1000) return;
  try {
    ApplyRetention();
  } catch (const std::exception& e) {  // a database read failed: next hour, again
    spdlog::error("retention of recordings: {}", e.what());
  }
}

void Persistence::ApplyRetention() {
  last_retention_ms_ = UnixNowMs();
  if (options_.retention_days <= 0.0) return;
  const auto cutoff_ms = last_retention_ms_ - static_cast<std::int64_t>(options_.retention_days * 86400e3);
  std::size_t deleted = 0;
  for (const auto& r : store_->RecordingsOlderThan(cutoff_ms)) {
    if (r.status == "open" || r.status == "deleted") continue;
    std::error_code error;
    std::filesystem::remove(r.path, error);
    store_->MarkRecordingDeleted(r.path);
    ++deleted;
  }
  if (deleted) spdlog::info("retention: deleted {} recordings older than {} days", deleted, options_.retention_days);
}

}  // namespace hapsim::service
