// Trial recording and replay, measured side by side in one run:
//  1. the tick's cost of recording: a tissue_block session's step alone, then
//     the same steps with the recorder's OnTick (a push into its ring, and the
//     state hash at each checkpoint) — the difference is what recording adds
//     to every tick;
//  2. a 10-minute scripted trial recorded through the real writer thread
//     (file size, bytes per tick);
//  3. that trial replayed with hapsim-replay's Replay(): real-time factor and
//     every checkpoint's hash;
//  4. seeking in it as a replay session does: forward to 90 % (a re-run from
//     the start that keeps states at checkpoints), then back to 55 % (from
//     the nearest kept state), against a re-run from the start to 55 %; and
//     what a kept state costs (Scene::SaveState(): time and heap; RestoreState()).
// A plain program (not Google Benchmark): each figure is one long run.
//   build/bin/bench_recording_replay [SCENE [TRIAL_S]]   (default tissue_block 600)
#include <malloc.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include "hapsim/recording/checkpoint_states.h"
#include "hapsim/recording/recording_service.h"
#include "hapsim/recording/replay.h"

namespace {

using hapsim::service::TickInput;
using hapsim::service::TickOutcome;

// A trainee's needle: presses of 3-8 mm at varying speeds with pauses, a
// little tremor, poses fresh every tick.
TickInput ScriptedTick(std::uint64_t tick) {
  TickInput in;
  in.tick = tick;
  const double t = static_cast<double>(tick) * 1e-3;
  const double cycle_s = 4.0 + std::sin(0.05 * t);
  const double phase = std::fmod(t, cycle_s) / cycle_s;
  const double depth_m = (0.003 + 0.0025 * (1.0 + std::sin(0.3 * t))) * std::max(0.0, std::sin(M_PI * phase));
  in.tool.valid = true;
  in.tool.tip_W_m = Eigen::Vector3d(0.004 * std::sin(0.1 * t) + 2e-5 * std::sin(53.0 * t),
                                    0.003 * std::cos(0.07 * t) + 2e-5 * std::cos(47.0 * t), 0.001 - depth_m);
  in.tool.velocity_W_m_per_s = Eigen::Vector3d(4e-4 * std::cos(0.1 * t), -2.1e-4 * std::sin(0.07 * t), 0.0);
  in.device_id = 1;
  in.pose_seq = tick;
  in.fresh_pose = true;
  return in;
}

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Seconds per tick of `ticks` scripted ticks on a fresh scene, with the
// recorder's tick part when `recorder` is given.
double StepCost(const std::string& scene_name, std::uint64_t ticks, hapsim::service::SessionRecorder* recorder,
                hapsim::service::RecordingService* service) {
  auto scene = hapsim::core::MakeScene({scene_name, {}});
  const auto start = std::chrono::steady_clock::now();
  double writer_wait_s = 0.0;
  for (std::uint64_t tick = 0; tick < ticks; ++tick) {
    const TickInput in = ScriptedTick(tick);
    hapsim::service::StepScene(*scene, in, 1e-3);
    if (recorder) {
      recorder->OnTick(TickOutcome{in, *scene, scene->ForceModel().state, scene->ToolForce_W_N().norm()});
      if ((tick + 1) % 2000 == 0) {  // let the writer drain (not counted: it is another thread's work)
        const auto flush = std::chrono::steady_clock::now();
        service->Flush();
        writer_wait_s += Seconds(flush);
      }
    }
  }
  return (Seconds(start) - writer_wait_s) / static_cast<double>(ticks);
}

// Heap in use [MB] (glibc's count of allocated bytes: freed memory the
// allocator keeps does not hide a new allocation, as it would in the RSS).
double HeapInUseMB() { return static_cast<double>(mallinfo2().uordblks) / 1e6; }

// Re-runs `recording` to the state before `next_tick`, from the nearest of `kept`, keeping states on the way.
hapsim::service::ReplayResult SeekTo(std::span<const std::uint8_t> recording, std::uint64_t next_tick,
                                     hapsim::service::CheckpointStates* kept) {
  hapsim::service::ReplayOptions options;
  options.until_tick = next_tick - 1;
  if (kept) {
    if (const auto nearest = kept->Nearest(next_tick)) options.from = {nearest->scene, nearest->next_tick};
    options.after_matched_checkpoint = [kept](const hapsim::service::RecordedCheckpoint& c,
                                              const hapsim::core::Scene& at) { kept->Offer(c.tick + 1, at); };
  }
  return hapsim::service::Replay(recording, options);
}

// 4. Seeking: forward from the start, back from a kept state, and a kept state's cost.
bool MeasureSeeks(const std::string& scene, std::span<const std::uint8_t> recording, std::uint64_t ticks) {
  const std::uint64_t first = hapsim::service::ReadRecordingHeader(recording).first_tick;
  hapsim::service::CheckpointStates kept(first, hapsim::service::CheckpointStates::SpacingFor(
                                                    ticks, hapsim::service::CheckpointStates::kDefaultMaxStates, 1));
  const auto forward = SeekTo(recording, first + ticks * 9 / 10, &kept);
  const std::uint64_t target = first + ticks * 11 / 20 + 437;  // between checkpoints
  const auto back = SeekTo(recording, target, &kept);
  const auto reference = SeekTo(recording, target, nullptr);
  const bool same = forward.ok() && back.ok() && back.scene->StateHash() == reference.scene->StateHash();
  std::printf(
      "seek forward to 90 %%: %llu ticks re-run in %.2f s (%zu states kept, one per %llu ticks); back to 55 %%: "
      "%llu ticks re-run in %.3f s, against %.2f s from the start; same state hash: %s\n",
      static_cast<unsigned long long>(forward.ticks_run), forward.elapsed_s, kept.size(),
      static_cast<unsigned long long>(kept.spacing_ticks()), static_cast<unsigned long long>(back.ticks_run),
      back.elapsed_s, reference.elapsed_s, same ? "yes" : "NO");
  std::vector<std::unique_ptr<const hapsim::core::Scene>> saved;
  const double before_MB = HeapInUseMB();
  const auto save_start = std::chrono::steady_clock::now();
  for (int i = 0; i < 10; ++i) saved.push_back(back.scene->SaveState());
  const double save_s = Seconds(save_start) / 10.0, saved_MB = (HeapInUseMB() - before_MB) / 10.0;
  const auto restore_start = std::chrono::steady_clock::now();
  auto restored = hapsim::core::MakeScene({scene, {}});
  const double build_s = Seconds(restore_start);
  restored->RestoreState(*saved.front());
  std::printf(
      "a kept state (%s): saved in %.2f ms, %.2f MB of heap; restored in %.1f ms (building the scene %.1f ms)\n",
      scene.c_str(), save_s * 1e3, saved_MB, Seconds(restore_start) * 1e3, build_s * 1e3);
  return same;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string scene = argc > 1 ? argv[1] : "tissue_block";
  const double trial_s = argc > 2 ? std::atof(argv[2]) : 600.0;
  const auto ticks = static_cast<std::uint64_t>(trial_s * 1000.0);
  const auto dir =
      std::filesystem::temp_directory_path() / ("hapsim-bench-recording-" + std::to_string(std::random_device{}()));
  hapsim::service::RecordingOptions options;
  options.directory = dir.string();
  hapsim::service::RecordingService service(options);

  // 1. The tick's cost, alternating baseline and recorded runs of 60 s of trial each.
  const std::uint64_t cost_ticks = 60000;
  double base_s = 0.0, rec_s = 0.0;
  for (int round = 0; round < 3; ++round) {
    base_s += StepCost(scene, cost_ticks, nullptr, nullptr) / 3.0;
    auto recorder = service.Attach({"cost", std::to_string(round), scene, {}, "", "", 1e-3});
    rec_s += StepCost(scene, cost_ticks, recorder.get(), &service) / 3.0;
  }
  std::printf("%s tick: step %.2f us, step + recorder %.2f us: recording adds %.3f us per tick (%.2f %% of the step)\n",
              scene.c_str(), base_s * 1e6, rec_s * 1e6, (rec_s - base_s) * 1e6, 100.0 * (rec_s - base_s) / base_s);

  // 2. A whole trial through the writer thread.
  const auto record_start = std::chrono::steady_clock::now();
  {
    auto recorder = service.Attach({"trial", "bench", scene, {}, "", "", 1e-3});
    StepCost(scene, ticks, recorder.get(), &service);
  }
  service.Flush();
  service.Flush();  // the session gone: its trial ends
  const double record_s = Seconds(record_start);
  std::string path;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir / "trial")) path = e.path().string();
  const auto bytes = std::filesystem::file_size(path);
  std::printf("recorded %.0f s of trial (%llu ticks) in %.1f s: %llu bytes, %.1f bytes per tick, %.1f MB per hour\n",
              trial_s, static_cast<unsigned long long>(ticks), record_s, static_cast<unsigned long long>(bytes),
              static_cast<double>(bytes) / static_cast<double>(ticks),
              static_cast<double>(bytes) / trial_s * 3600.0 / 1e6);

  // The writer's part per block: encoding 50 ticks (one flush interval at 1 kHz).
  {
    std::vector<TickInput> inputs;
    for (std::uint64_t tick = 0; tick < 50000; ++tick) inputs.push_back(ScriptedTick(tick));
    hapsim::service::TickBlockEncoder encoder;
    std::size_t bytes_out = 0;
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t at = 0; at < inputs.size(); at += 50)
      bytes_out += encoder.Encode(std::span(inputs).subspan(at, 50)).size();
    const double each_s = Seconds(start) / 1000.0;
    std::printf("writer: a 50-tick block encoded in %.2f us (%zu bytes, zstd level %d)\n", each_s * 1e6,
                bytes_out / 1000, hapsim::service::TickBlockEncoder::kCompressionLevel);
  }

  // 3. Its replay.
  const auto recording = hapsim::service::ReadRecordingBytes(path);
  const auto r = hapsim::service::Replay(recording);
  std::printf("replayed %llu ticks in %.2f s: %.1fx real time; checkpoints %llu of %llu reached with the same hash%s\n",
              static_cast<unsigned long long>(r.ticks_run), r.elapsed_s,
              static_cast<double>(r.ticks_run) * 1e-3 / r.elapsed_s,
              static_cast<unsigned long long>(r.checkpoints_matched),
              static_cast<unsigned long long>(r.summary.checkpoints), r.ok() ? "" : " — DIVERGED");
  const bool seeks_ok = MeasureSeeks(scene, recording, r.ticks_run);
  service.Stop();
  std::filesystem::remove_all(dir);
  return r.ok() && r.checkpoints_matched == r.summary.checkpoints && seeks_ok ? 0 : 1;
}
