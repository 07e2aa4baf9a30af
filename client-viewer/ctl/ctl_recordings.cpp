// hapsim-ctl's trial-recording commands: list, fetch (to replay with
// hapsim-replay) and delete.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "ctl_commands.h"
#include "hapsim/common/local_time.h"

namespace hapsim::ctl {

namespace {

void PrintReplay(const hapsim::v1::ReplayInfo& r) {
  std::printf("%s recording=%s trial_s=%.3f length_s=%.3f speed=%.2f paused=%d ended=%d checkpoints=%" PRIu64
              " matched=%" PRIu64 " diverged=%" PRIu64 " rerun_ticks=%" PRIu64 " kept_states=%" PRIu64 "\n",
              r.session().session_id().c_str(), r.recording_id().c_str(), r.trial_s(), r.trial_length_s(), r.speed(),
              r.session().paused() ? 1 : 0, r.ended() ? 1 : 0, r.checkpoints(), r.checkpoints_matched(),
              r.checkpoints_diverged(), r.rerun_ticks(), r.kept_states());
}

bool ParseNumber(const std::string& text, const char* flag, double* out) {
  if (text.empty()) return true;
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(*out)) {
    std::fprintf(stderr, "hapsim-ctl: %s wants a number, not '%s'\n", flag, text.c_str());
    return false;
  }
  return true;
}

}  // namespace

int RunReplay(CommandCall& call) {
  hapsim::v1::OpenReplayRequest req;
  req.set_recording_id(call.id);
  double speed = 1.0, start_s = 0.0;
  if (!ParseNumber(call.flags.speed, "--speed", &speed) || !ParseNumber(call.flags.start_s, "--start-s", &start_s)) {
    return 2;
  }
  req.set_speed(speed);
  req.set_start_s(start_s);
  req.set_paused(call.flags.paused);
  hapsim::v1::ReplayInfo r;
  const auto s = call.stub->OpenReplay(&call.context, req, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintReplay(r);
  std::printf("watch it: hapsim-viewer --session %s\n", r.session().session_id().c_str());
  return 0;
}

int RunReplayInfo(CommandCall& call) {
  hapsim::v1::SessionRef ref;
  ref.set_session_id(call.id);
  hapsim::v1::ReplayInfo r;
  const auto s = call.stub->GetReplay(&call.context, ref, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintReplay(r);
  return 0;
}

int RunStep(CommandCall& call) {
  hapsim::v1::StepReplayRequest req;
  req.set_session_id(call.id);
  double ticks = 1.0;
  if (!ParseNumber(call.flags.ticks, "--ticks", &ticks)) return 2;
  if (!(ticks >= 1.0 && ticks <= 100000.0 && ticks == std::floor(ticks))) {
    std::fprintf(stderr, "hapsim-ctl: --ticks must be a whole number in [1, 100000]\n");
    return 2;
  }
  req.set_ticks(static_cast<std::uint32_t>(ticks));
  hapsim::v1::ReplayInfo r;
  const auto s = call.stub->StepReplay(&call.context, req, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintReplay(r);
  return 0;
}

int RunSeek(CommandCall& call) {
  hapsim::v1::SeekReplayRequest req;
  req.set_session_id(call.id);
  double to_s = 0.0;
  if (call.flags.to_s.empty()) {
    std::fprintf(stderr, "hapsim-ctl seek: give --to-s SECONDS\n");
    return 2;
  }
  if (!ParseNumber(call.flags.to_s, "--to-s", &to_s)) return 2;
  req.set_trial_s(to_s);
  hapsim::v1::ReplayInfo r;
  const auto s = call.stub->SeekReplay(&call.context, req, &r);
  if (!s.ok()) return ReportFailure(s);
  PrintReplay(r);
  return 0;
}

int RunRecordings(CommandCall& call) {
  hapsim::v1::RecordingQuery q;
  q.set_session_id(call.id);
  hapsim::v1::RecordingList list;
  const auto s = call.stub->ListRecordings(&call.context, q, &list);
  if (!s.ok()) return ReportFailure(s);
  std::printf("%-40s %-10s %5s %-12s %-14s %-19s %9s %10s %s\n", "id", "session", "trial", "trainee", "scene",
              "started", "ticks", "bytes", "status");
  for (const auto& r : list.recordings()) {
    std::printf("%-40s %-10s %5" PRIu64 " %-12s %-14s %-19s %9" PRIu64 " %10" PRIu64 " %s\n", r.id().c_str(),
                r.session_id().c_str(), r.trial(), r.trainee().c_str(), r.scene().c_str(),
                common::LocalTimeText(r.started_unix_ms(), "%Y-%m-%d %H:%M:%S").c_str(), r.ticks(), r.bytes(),
                r.status().c_str());
  }
  return 0;
}

int RunFetchRecording(CommandCall& call) {
  std::string out = call.flags.output;
  if (out.empty()) {  // the file name part of the id
    const auto slash = call.id.find_last_of('/');
    out = slash == std::string::npos ? call.id : call.id.substr(slash + 1);
  }
  hapsim::v1::RecordingRef ref;
  ref.set_id(call.id);
  auto reader = call.stub->GetRecording(&call.context, ref);
  std::FILE* f = std::fopen(out.c_str(), "wb");
  if (!f) {
    std::fprintf(stderr, "hapsim-ctl: cannot write %s\n", out.c_str());
    reader->Finish();
    return 1;
  }
  hapsim::v1::RecordingChunk chunk;
  std::uint64_t bytes = 0;
  bool written = true;
  while (reader->Read(&chunk)) {
    written = written && std::fwrite(chunk.data().data(), 1, chunk.data().size(), f) == chunk.data().size();
    bytes += chunk.data().size();
  }
  const auto s = reader->Finish();
  written = std::fclose(f) == 0 && written;
  if (!s.ok()) {
    std::remove(out.c_str());
    return ReportFailure(s);
  }
  if (!written) {
    std::fprintf(stderr, "hapsim-ctl: cannot write %s\n", out.c_str());
    return 1;
  }
  std::printf("wrote %" PRIu64 " bytes to %s (replay it: hapsim-replay %s)\n", bytes, out.c_str(), out.c_str());
  return 0;
}

int RunDeleteRecording(CommandCall& call) {
  hapsim::v1::RecordingRef ref;
  ref.set_id(call.id);
  hapsim::v1::DeleteRecordingResponse r;
  const auto s = call.stub->DeleteRecording(&call.context, ref, &r);
  if (!s.ok()) return ReportFailure(s);
  std::printf("deleted %s\n", call.id.c_str());
  return 0;
}

}  // namespace hapsim::ctl
