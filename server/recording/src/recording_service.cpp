#include "hapsim/recording/recording_service.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "hapsim/common/thread_setup.h"

namespace hapsim::service {

std::int64_t UnixNowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// How often the database's index hears how far an open trial's file has got.
constexpr std::int64_t kProgressEveryMs = 5000;

struct RecordingService::Track {
  std::shared_ptr<SessionRecorder> recorder;
  std::optional<RecordingFile> file;
  RecordingHeader header;       // the open trial's
  std::uint64_t next_tick = 0;  // the tick the next record should carry
  std::uint64_t trial = 0;
  bool started = false;  // a trial has begun (the next reset starts another)
  bool broken = false;   // ticks were lost: nothing is written until the next reset
  std::uint64_t trial_ticks = 0;
  std::int64_t last_progress_ms = 0;
  std::vector<TickRecord> drained;
  std::vector<TickInput> block;
};

RecordingService::RecordingService(RecordingOptions options, std::function<void(const RecordingEvent&)> on_event)
    : options_(std::move(options)), on_event_(std::move(on_event)) {
  if (options_.checkpoint_every_ticks == 0) throw std::invalid_argument("checkpoint interval must be >= 1 tick");
  if (options_.flush_interval_ms <= 0) throw std::invalid_argument("flush interval must be > 0 ms");
  std::filesystem::create_directories(options_.directory);
  thread_ = std::thread([this] { Run(); });
}

RecordingService::~RecordingService() { Stop(); }

std::shared_ptr<SessionRecorder> RecordingService::Attach(RecordedSession who, std::uint64_t first_tick,
                                                          std::optional<RecordingResume> resume) {
  auto track = std::make_unique<Track>();
  const std::uint64_t trial_first_tick = resume ? resume->header.first_tick : first_tick;
  track->recorder = std::make_shared<SessionRecorder>(std::move(who), options_.queue_ticks,
                                                      options_.checkpoint_every_ticks, trial_first_tick);
  track->next_tick = first_tick;
  if (resume) {  // the writer appends to the restored trial's file from its first pass
    track->header = resume->header;
    track->file.emplace(RecordingFile::Reopen(resume->path, resume->valid_bytes));
    track->trial = resume->header.trial;
    track->trial_ticks = resume->next_tick - resume->header.first_tick;
    track->started = true;
    std::string error;
    const auto mark = EncodeRecord(RecordKind::kResumed, resume->next_tick, 0, EncodeResumed(UnixNowMs()));
    if (!track->file->Append(mark, &error)) throw std::runtime_error(error);
  }
  auto recorder = track->recorder;
  std::lock_guard lock(mutex_);
  attached_.push_back(std::move(track));
  return recorder;
}

void RecordingService::Flush() {
  std::unique_lock lock(mutex_);
  if (stop_) return;
  const std::uint64_t ticket = ++flush_requested_;
  wake_.notify_all();
  flushed_.wait(lock, [&] { return flush_done_ >= ticket || stop_; });
}

void RecordingService::Stop() {
  {
    std::lock_guard lock(mutex_);
    if (stop_) return;
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  flushed_.notify_all();
}

RecordingStats RecordingService::stats() const {
  std::lock_guard lock(mutex_);
  RecordingStats s = stats_;
  for (const auto& t : tracks_) s.ticks_lost += t->recorder->lost_ticks();
  for (const auto& t : attached_) s.ticks_lost += t->recorder->lost_ticks();
  return s;
}

void RecordingService::Run() {
  common::NameThisThread("hapsim-record");
  common::RunThisThreadOnlyWhenIdle();  // the ticks first: 4 s of queue absorb a busy spell
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait_for(lock, std::chrono::milliseconds(options_.flush_interval_ms),
                   [&] { return stop_ || flush_requested_ > flush_done_; });
    const bool final_pass = stop_;
    const std::uint64_t ticket = flush_requested_;
    lock.unlock();
    Pass(final_pass);
    lock.lock();
    flush_done_ = ticket;
    flushed_.notify_all();
    if (final_pass) return;
  }
}

void RecordingService::Pass(bool final_pass) {
  {
    std::lock_guard lock(mutex_);
    for (auto& t : attached_) tracks_.push_back(std::move(t));
    attached_.clear();
  }
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    Track& track = **it;
    // Gone: only this track holds the recorder, so no tick can push any more.
    const bool session_gone = track.recorder.use_count() == 1;
    track.drained.clear();
    track.recorder->Drain(&track.drained);
    WriteRecords(track, track.drained);
    if (session_gone && !final_pass) {
      if (track.file) EndTrial(track, true);
      std::lock_guard lock(mutex_);
      stats_.ticks_lost += track.recorder->lost_ticks();
      it = tracks_.erase(it);
      continue;
    }
    const std::int64_t now_ms = UnixNowMs();
    if (track.file && now_ms - track.last_progress_ms >= kProgressEveryMs) {
      track.last_progress_ms = now_ms;
      Emit(track, RecordingEvent::Kind::kProgress);
    }
    ++it;
  }
  const std::int64_t now_ms = UnixNowMs();
  if (options_.fsync_interval_ms > 0 && (final_pass || now_ms - last_sync_ms_ >= options_.fsync_interval_ms)) {
    last_sync_ms_ = now_ms;
    for (auto& t : tracks_) {
      std::string error;
      if (t->file && !t->file->Sync(&error)) Break(*t, error);
    }
  }
  std::lock_guard lock(mutex_);
  stats_.open_trials = 0;
  for (const auto& t : tracks_) stats_.open_trials += t->file.has_value();
}

void RecordingService::WriteRecords(Track& track, const std::vector<TickRecord>& records) {
  auto write_block = [&] {
    if (track.block.empty() || !track.file) return;
    const auto payload = encoder_.Encode(track.block);
    const auto first = track.block.front().tick;
    const auto count = static_cast<std::uint32_t>(track.block.size());
    track.block.clear();
    if (!Write(track, EncodeRecord(RecordKind::kTicks, first, count, payload))) return;
    track.trial_ticks += count;
    std::lock_guard lock(mutex_);
    stats_.ticks_written += count;
  };
  for (const TickRecord& r : records) {
    const TickInput& in = r.input;
    if (in.tick != track.next_tick && track.file) {  // the queue was full: these ticks are gone
      write_block();
      const std::uint64_t lost = in.tick - track.next_tick;
      Write(track, EncodeRecord(RecordKind::kGap, track.next_tick, static_cast<std::uint32_t>(lost), {}));
      Break(track, std::to_string(lost) + " ticks lost from tick " + std::to_string(track.next_tick) +
                       " (the recording writer fell behind)");
    }
    track.next_tick = in.tick + 1;
    if (in.reset && track.started) {  // the next trial
      write_block();
      if (track.file) EndTrial(track, true);
      ++track.trial;
      track.broken = false;
    }
    track.started = true;
    if (track.broken) continue;
    if (!track.file) OpenTrial(track, in);
    if (!track.file) continue;
    track.block.push_back(in);
    if (r.has_hash) {
      write_block();
      Write(track, EncodeRecord(RecordKind::kCheckpoint, in.tick, 1, EncodeCheckpoint(r.state_hash, r.sim_time_s)));
    } else if (track.block.size() >= kMaxTicksPerBlock) {
      write_block();
    }
  }
  write_block();
}

void RecordingService::OpenTrial(Track& track, const TickInput& first) {
  const RecordedSession& who = track.recorder->who();
  RecordingHeader& h = track.header;
  h = RecordingHeader{};
  h.session_id = who.session_id;
  h.run_id = who.run_id;
  h.trial = track.trial;
  h.scene = who.scene;
  h.params = who.params;
  h.owner = who.owner;
  h.class_name = who.class_name;
  h.tick_period_s = who.tick_period_s;
  h.first_tick = first.tick;
  h.started_unix_ms = UnixNowMs();
  h.checkpoint_every_ticks = track.recorder->checkpoint_every_ticks();
  h.written_by = "hapsim-server";
  char name[64];
  std::snprintf(name, sizeof name, "-t%04llu.hrec", static_cast<unsigned long long>(track.trial));
  const auto dir = std::filesystem::path(options_.directory) / who.session_id;
  const std::string path = (dir / (who.run_id + name)).string();
  try {
    std::filesystem::create_directories(dir);
    track.file.emplace(RecordingFile::Create(path, h));
  } catch (const std::exception& e) {
    track.file.reset();
    track.broken = true;
    {
      std::lock_guard lock(mutex_);
      ++stats_.write_errors;
    }
    spdlog::error("session '{}': trial {} is not recorded: {}", who.session_id, track.trial, e.what());
    return;
  }
  track.trial_ticks = 0;
  track.last_progress_ms = h.started_unix_ms;
  Emit(track, RecordingEvent::Kind::kOpened);
}

void RecordingService::EndTrial(Track& track, bool clean) {
  if (clean)
    Write(track,
          EncodeRecord(RecordKind::kEnd, track.header.first_tick, static_cast<std::uint32_t>(track.trial_ticks), {}));
  if (!track.file) return;
  std::string error;
  if (options_.fsync_interval_ms > 0) track.file->Sync(&error);
  Emit(track, RecordingEvent::Kind::kClosed);
  track.file.reset();
}

void RecordingService::Break(Track& track, const std::string& problem) {
  spdlog::warn("session '{}': recording of trial {} stops: {}", track.header.session_id, track.trial, problem);
  if (track.file) Emit(track, RecordingEvent::Kind::kBroken, problem);
  track.file.reset();
  track.block.clear();
  track.broken = true;
}

bool RecordingService::Write(Track& track, std::span<const std::uint8_t> bytes) {
  if (!track.file) return false;
  std::string error;
  if (track.file->Append(bytes, &error)) {
    std::lock_guard lock(mutex_);
    stats_.bytes_written += bytes.size();
    return true;
  }
  {
    std::lock_guard lock(mutex_);
    ++stats_.write_errors;
  }
  Break(track, error);
  return false;
}

void RecordingService::Emit(const Track& track, RecordingEvent::Kind kind, const std::string& problem) {
  if (!on_event_ || !track.file) return;
  RecordingEvent e;
  e.kind = kind;
  e.path = track.file->path();
  e.session_id = track.header.session_id;
  e.run_id = track.header.run_id;
  e.scene = track.header.scene;
  e.owner = track.header.owner;
  e.class_name = track.header.class_name;
  e.trial = track.trial;
  e.started_unix_ms = track.header.started_unix_ms;
  if (kind == RecordingEvent::Kind::kClosed) e.ended_unix_ms = UnixNowMs();
  e.ticks = track.trial_ticks;
  e.bytes = track.file->bytes();
  e.problem = problem;
  on_event_(e);
}

}  // namespace hapsim::service
