// `hapsim-ctl watch`: the class view as a table, redrawn in place on a
// terminal (like top) or printed block after block into a pipe or file.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <string>

#include "ctl_commands.h"
#include "hapsim/viewer/connection.h"

namespace hapsim::ctl {

namespace {

// --rate-hz and --count; false (with the message printed) when malformed.
bool ParseWatchFlags(const CommandFlags& flags, hapsim::v1::WatchClassRequest* req, long* count) {
  if (!flags.rate_hz.empty()) {
    char* end = nullptr;
    req->set_rate_hz(std::strtod(flags.rate_hz.c_str(), &end));
    if (*end != '\0' || !(req->rate_hz() >= 0.1 && req->rate_hz() <= 50.0)) {
      std::fprintf(stderr, "hapsim-ctl: --rate-hz wants [0.1, 50], got '%s'\n", flags.rate_hz.c_str());
      return false;
    }
  }
  if (!flags.count.empty()) {
    char* end = nullptr;
    *count = std::strtol(flags.count.c_str(), &end, 10);
    if (*end != '\0' || *count < 1) {
      std::fprintf(stderr, "hapsim-ctl: --count wants a whole number >= 1, got '%s'\n", flags.count.c_str());
      return false;
    }
  }
  return true;
}

// What the table remembers across updates: each session's last three
// events and how many it has seen.
struct WatchMemory {
  std::map<std::string, std::deque<std::string>> recent;  // session -> last events, newest last
  std::map<std::string, std::uint64_t> event_counts;
};

void PrintWatchHeader(const std::string& class_name, const hapsim::v1::ClassStatus& status) {
  std::printf("class %s  update %llu  (%d sessions%s)\n", class_name.empty() ? "(all)" : class_name.c_str(),
              static_cast<unsigned long long>(status.seq()), status.sessions_size(),
              status.missing_sessions_size() ? ", some not running" : "");
  std::printf("%-10s %-10s %-12s %-6s %-9s %8s %-8s %8s %8s %6s %8s %-7s %s\n", "SESSION", "TRAINEE", "SCENE", "DEVICE",
              "CONTACT", "DEPTH_MM", "LAYER", "FORCE_N", "PEAK_N", "LATE", "EVENTS", "SCORE", "RECENT EVENTS");
}

void PrintWatchRow(const hapsim::v1::SessionStatus& s, WatchMemory* memory) {
  auto& last = memory->recent[s.session_id()];
  for (const auto& e : s.events()) {
    ++memory->event_counts[s.session_id()];
    last.push_back(e.kind() + "@" + std::to_string(e.t_s()).substr(0, 6) + "s");
    if (last.size() > 3) last.pop_front();
  }
  std::string events;
  for (const auto& e : last) events += (events.empty() ? "" : " ") + e;
  char score[16] = "-";
  if (s.experts() > 0) std::snprintf(score, sizeof score, "%.2f", s.score());
  std::printf("%-10.10s %-10.10s %-12.12s %-6s %-9.9s %8.2f %-8.8s %8.3f %8.3f %6llu %8llu %-7s %s%s\n",
              s.session_id().c_str(), s.trainee().c_str(), s.scene().c_str(), s.device_streaming() ? "yes" : "no",
              s.contact_state().c_str(), s.tip_depth_m() * 1e3, s.layer_name().empty() ? "-" : s.layer_name().c_str(),
              s.force_n(), s.peak_tool_force_n(), static_cast<unsigned long long>(s.late_ticks()),
              static_cast<unsigned long long>(memory->event_counts[s.session_id()]), score, events.c_str(),
              s.paused() ? " [paused]" : "");
}

}  // namespace

int Watch(CommandCall& call) {
  hapsim::v1::WatchClassRequest req;
  req.set_class_name(call.id);
  long count = 0;
  if (!ParseWatchFlags(call.flags, &req, &count)) return 2;
  grpc::ClientContext ctx;  // no deadline: it streams until --count or Ctrl-C
  hapsim::viewer::AddToken(&ctx, call.token);
  auto reader = call.stub->WatchClass(&ctx, req);
  const bool terminal = ::isatty(STDOUT_FILENO) != 0;
  WatchMemory memory;
  hapsim::v1::ClassStatus status;
  long shown = 0;
  while (reader->Read(&status)) {
    if (terminal) std::printf("\033[H\033[2J");
    PrintWatchHeader(call.id, status);
    for (const auto& s : status.sessions()) PrintWatchRow(s, &memory);
    for (const auto& m : status.missing_sessions()) std::printf("%-10.10s (not running)\n", m.c_str());
    if (!terminal) std::printf("\n");
    std::fflush(stdout);
    if (count > 0 && ++shown >= count) {
      ctx.TryCancel();
      break;
    }
  }
  const auto s = reader->Finish();
  if (count > 0 && shown >= count) return 0;
  return s.ok() ? 0 : ReportFailure(s);
}

}  // namespace hapsim::ctl
