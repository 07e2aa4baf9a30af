// hapsim-ctl's trial-recording commands: list, fetch (to replay with
// hapsim-replay) and delete.
#include <cinttypes>
#include <cstdio>
#include <ctime>

#include "ctl_commands.h"

namespace hapsim::ctl {

namespace {

std::string LocalTime(std::int64_t unix_ms) {
  if (unix_ms <= 0) return "-";
  const std::time_t t = static_cast<std::time_t>(unix_ms / 1000);
  std::tm local{};
  localtime_r(&t, &local);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &local);
  return text;
}

}  // namespace

int RunRecordings(CommandCall& call) {
  hapsim::v1::RecordingQuery q;
  q.set_session_id(call.id);
  hapsim::v1::RecordingList list;
  const auto s = call.stub->ListRecordings(&call.context, q, &list);
  if (!s.ok()) return ReportFailure(s);
  std::printf("%-40s %-10s %5s %-12s %-14s %-19s %9s %10s %s\n", "id", "session", "trial", "trainee", "scene",
              "started", "length_s", "bytes", "status");
  for (const auto& r : list.recordings()) {
    std::printf("%-40s %-10s %5" PRIu64 " %-12s %-14s %-19s %9.1f %10" PRIu64 " %s\n", r.id().c_str(),
                r.session_id().c_str(), r.trial(), r.trainee().c_str(), r.scene().c_str(),
                LocalTime(r.started_unix_ms()).c_str(), static_cast<double>(r.ticks()) * 1e-3, r.bytes(),
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
