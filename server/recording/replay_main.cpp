// hapsim-replay: re-runs a trial recording and checks that it reaches the
// recorded state hash at every checkpoint (on this machine or any other: the
// core's results do not depend on the CPU). Paced at a chosen speed, or as
// fast as the machine goes; optionally printing the tool and tissue state
// every N ticks to step through a trial.
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <thread>

#include "hapsim/common/flags.h"
#include "hapsim/recording/replay.h"

namespace {

using hapsim::service::RecordingError;
using hapsim::service::ReplayOptions;

void PrintHeader(const hapsim::service::RecordingHeader& h) {
  std::printf("trial %" PRIu64 " of session '%s' (run %s), trainee '%s', class '%s'\n", h.trial, h.session_id.c_str(),
              h.run_id.c_str(), h.owner.c_str(), h.class_name.c_str());
  std::printf("scene %s, %zu parameter(s) set, tick %.6g s, first tick %" PRIu64 ", checkpoint every %u ticks\n",
              h.scene.c_str(), h.params.size(), h.tick_period_s, h.first_tick, h.checkpoint_every_ticks);
}

}  // namespace

int main(int argc, char** argv) {
  double speed = 0.0;
  int print_every = 0;
  double until_s = 0.0;
  std::vector<std::string> files;
  hapsim::common::Flags flags("hapsim-replay",
                              "Re-runs a trial recording (.hrec) and checks the recorded state hash at every "
                              "checkpoint. Exit 0: every checkpoint reached; 1: the state diverged; 3: the file "
                              "cannot be read.",
                              "[flags] FILE.hrec");
  flags.Add("speed", &speed, "play at this multiple of real time (0: as fast as possible)");
  flags.Add("print-every-ticks", &print_every, "print the tool and tissue state every N ticks (0: never)");
  flags.Add("until-s", &until_s, "stop after this much of the trial [s] (0: the whole trial)");
  flags.AllowPositionals(&files);
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case hapsim::common::Flags::Result::kHelp:
      std::printf("%s", flags.Help().c_str());
      return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::printf("%s", flags.Version().c_str());
      return 0;
    case hapsim::common::Flags::Result::kError:
      std::fprintf(stderr, "hapsim-replay: %s\n", error.c_str());
      return 2;
    case hapsim::common::Flags::Result::kOk:
      break;
  }
  const std::string range =
      hapsim::common::FirstFlagOutOfRange({{speed >= 0.0 && speed <= 1000.0, "--speed", "[0, 1000]"},
                                           {print_every >= 0, "--print-every-ticks", "[0, 2^31)"},
                                           {until_s >= 0.0 && until_s <= hapsim::common::kMaxFlagSeconds, "--until-s",
                                            hapsim::common::kMaxFlagSecondsRange}});
  if (!range.empty() || files.size() != 1) {
    std::fprintf(stderr, "hapsim-replay: %s\n", range.empty() ? "give one recording file" : range.c_str());
    return 2;
  }
  try {
    const auto bytes = hapsim::service::ReadRecordingBytes(files[0]);
    const auto header = hapsim::service::ReadRecordingHeader(bytes);
    PrintHeader(header);
    ReplayOptions options;
    if (until_s > 0.0)
      options.until_tick = header.first_tick + static_cast<std::uint64_t>(until_s / header.tick_period_s) - 1;
    const auto start = std::chrono::steady_clock::now();
    options.after_tick = [&](const hapsim::service::TickInput& in, const hapsim::core::Scene& scene) {
      const std::uint64_t n = in.tick - header.first_tick + 1;
      if (print_every > 0 && n % static_cast<std::uint64_t>(print_every) == 0) {
        const auto& tip = in.tool.tip_W_m;
        std::printf("tick %" PRIu64 "  t %.3f s  tip (%.4f, %.4f, %.4f) m  |F| %.3f N  layer %d  depth %.4f m%s%s\n",
                    in.tick, scene.SimTime_s(), tip.x(), tip.y(), tip.z(), scene.ToolForce_W_N().norm(),
                    scene.Status().current_layer, scene.Status().tip_depth_m, in.paused ? "  paused" : "",
                    in.tool.valid ? "" : "  (no tool)");
      }
      if (speed > 0.0) {
        std::this_thread::sleep_until(
            start + std::chrono::duration<double>(static_cast<double>(n) * header.tick_period_s / speed));
      }
    };
    const auto r = hapsim::service::Replay(bytes, options);
    const double trial_s = static_cast<double>(r.ticks_run) * header.tick_period_s;
    std::printf("replayed %" PRIu64 " ticks (%.3f s of the trial) in %.3f s: %.1fx real time\n", r.ticks_run, trial_s,
                r.elapsed_s, r.elapsed_s > 0 ? trial_s / r.elapsed_s : 0.0);
    std::printf("checkpoints: %" PRIu64 " of %" PRIu64 " recorded reached with the same state hash\n",
                r.checkpoints_matched, r.summary.checkpoints);
    if (r.summary.resumes)
      std::printf("the server restarted %" PRIu64 " time(s) during this trial\n", r.summary.resumes);
    if (r.summary.gap_at_tick) {
      std::printf("inputs were lost from tick %" PRIu64 " (the recorder fell behind): replay ends there\n",
                  *r.summary.gap_at_tick);
    }
    if (r.summary.damage) std::printf("reading stopped early: %s\n", r.summary.damage->what());
    std::printf("%s\n", r.summary.ended ? "the trial ended cleanly"
                                        : "the trial has no end record (still open, or the server stopped)");
    if (r.mismatch) {
      std::printf("STATE DIVERGED after tick %" PRIu64 ": recorded hash %016" PRIx64 ", replayed %016" PRIx64 "\n",
                  r.mismatch->tick, r.mismatch->recorded, r.mismatch->replayed);
      return 1;
    }
    return 0;
  } catch (const RecordingError& e) {
    std::fprintf(stderr, "hapsim-replay: %s: %s\n", files[0].c_str(), e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-replay: %s\n", e.what());
  }
  return 3;
}
