// hapsim-load: the load generator. N synthetic devices in one process (one
// DDS participant, one servo thread stepping all of them at the servo rate,
// each with its own safety chain) drive N sessions of a hapsim-server, which
// it can create and close itself. Prints a per-device table at exit and
// writes JSON/CSV summaries for scripts (the capacity benchmark).
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdio>
#include <string>
#include <vector>

#include "backends/synthetic_device.h"
#include "hapsim/bridge/device_dds.h"
#include "hapsim/bridge/device_flags.h"
#include "hapsim/common/flags.h"
#include "hapsim/common/shutdown_deadline.h"
#include "hapsim/load/load_plan.h"
#include "hapsim/load/load_report_format.h"
#include "hapsim/load/load_runner.h"
#include "load_sessions.h"
#include "stop_on_signal.h"

namespace {

constexpr const char* kSummary =
    "Load generator of hapsim: N synthetic haptic devices in one process, one DDS participant and one\n"
    "servo thread stepping all of them at the servo rate (absolute deadlines), each device on a clock of\n"
    "its own as a classroom's are: phases spread over the period (--clock-phase-spread) and rates off by\n"
    "up to --clock-rate-ppm (0 and 0: every device in lockstep, one wake per period). Device i has id\n"
    "--first-device-id + i and drives session <--session-prefix><i> (or the i-th of --sessions); it runs\n"
    "the common --script with seed --seed + i, read at a phase offset i * --phase-spread-s / N. Each\n"
    "device renders its force models through its own safety chain (clamp, rise limit, watchdog), as\n"
    "hapsim-bridge does. With --create SCENE it creates those sessions through the server's\n"
    "SessionService first (and closes them at exit unless --keep-sessions).\n\n"
    "Reports per device and in total: pose rate, models received, echoed pose seq first/last and\n"
    "regressions, round trip and model age p50/p99/max, watchdog warnings/fades/disarms (events),\n"
    "force clamps (ticks); the servo thread's own lateness; with --create or --server-stats, the server's\n"
    "counters of each session (late_ticks, device-clocked ticks, ...). A table on stdout at exit;\n"
    "--json/--csv write summaries. SIGINT/SIGTERM stop the run cleanly (the report is still written).\n"
    "Exit: 0 done, 1 runtime error (a session could not be created, a file not written), 2 bad flags.";

// Closes the sessions hapsim-load created when main() leaves, however it leaves.
struct CloseSessionsAtExit {
  hapsim::viewer::SessionClient* client = nullptr;
  std::vector<std::string> ids;
  ~CloseSessionsAtExit() {
    if (!client || ids.empty()) return;
    const std::string errors = hapsim::bridge::CloseSessions(*client, ids);
    if (errors.empty()) {
      spdlog::info("closed {} sessions", ids.size());
    } else {
      std::fprintf(stderr, "hapsim-load: cannot close sessions:\n%s\n", errors.c_str());
    }
  }
};

// The flags of hapsim-load.
struct LoadFlags {
  hapsim::bridge::LoadPlanOptions plan_options;
  std::string sessions, create_scene, params, json_file, csv_file, intervals_csv_file;
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  int devices = plan_options.devices, first_device_id = static_cast<int>(plan_options.first_device_id);
  double seconds = 0.0, rate_hz = 1000.0, interval_s = 0.0;
  bool keep_sessions = false, server_stats = false;
  hapsim::bridge::ScriptFlags script;
  hapsim::bridge::SafetyFlags safety;
  hapsim::bridge::PoseDeadbandFlags pose_deadband;
  hapsim::bridge::ProcessFlags process;
};

// In the order --help lists them.
void AddLoadFlags(hapsim::common::Flags& flags, LoadFlags* f) {
  flags.Add("devices", &f->devices, "number of synthetic devices (one session each)");
  flags.Add("session-prefix", &f->plan_options.session_prefix, "device i drives session <prefix><i>");
  flags.Add("sessions", &f->sessions,
            "explicit session ids a,b,c (one device each; overrides --devices/--session-prefix)");
  flags.Add("first-device-id", &f->first_device_id, "device id of device 0 (device i: this + i)");
  hapsim::bridge::AddScriptFlags(flags, &f->script, "base seed of the random_walk script (device i: seed + i)");
  flags.Add("phase-spread-s", &f->plan_options.phase_spread_s,
            "device i reads its script at t + i * spread / N [s] (0: all in lockstep)");
  flags.Add("clock-phase-spread", &f->plan_options.clock_phase_spread,
            "device i's servo clock ticks i / N of this many periods after device 0's, [0, 1]");
  flags.Add("clock-rate-ppm", &f->plan_options.clock_rate_ppm,
            "device clocks' rates spread evenly over +-this [ppm] (a crystal's error: tens to hundreds)");
  flags.Add("seconds", &f->seconds, "stop after this long [s] (0: until SIGINT/SIGTERM)");
  flags.Add("rate-hz", &f->rate_hz, "nominal servo rate of every device [Hz]");
  hapsim::bridge::AddPoseDeadbandFlags(flags, &f->pose_deadband);
  hapsim::bridge::AddSafetyFlags(flags, &f->safety);
  flags.Add("create", &f->create_scene, "create the sessions with this scene before starting (see hapsim-ctl scenes)");
  flags.Add("params", &f->params, "with --create: scene parameters k=v,k=v (SI, as hapsim-ctl create --param)");
  flags.Add("keep-sessions", &f->keep_sessions, "with --create: leave the sessions open at exit");
  flags.Add("server-stats", &f->server_stats, "read the server's session counters after the run even without --create");
  flags.Add("server", &f->connection.address, "gRPC address of the hapsim-server (for --create and --server-stats)");
  hapsim::viewer::AddConnectionFlags(&flags, &f->connection, &f->connection_flags);
  flags.Add("json", &f->json_file, "write the summary as JSON here");
  flags.Add("csv", &f->csv_file, "write the per-device summary as CSV here (last row: total)");
  flags.Add("interval-s", &f->interval_s,
            "also report round trip and model age per interval of this length [s] (0: off; in --json and "
            "--intervals-csv)");
  flags.Add("intervals-csv", &f->intervals_csv_file, "with --interval-s: write one CSV row per interval here");
  hapsim::bridge::AddProcessFlags(flags, &f->process);
}

// False (after saying which) if a flag is out of range or wrong with another;
// finishes the connection flags into f->connection.
bool CheckLoadFlags(LoadFlags* f) {
  const std::string out_of_range = hapsim::common::FirstFlagOutOfRange({
      {f->rate_hz >= 100.0 && f->rate_hz <= 10000.0, "--rate-hz", "[100, 10000]"},
      {f->seconds >= 0.0 && f->seconds <= hapsim::common::kMaxFlagSeconds, "--seconds",
       hapsim::common::kMaxFlagSecondsRange},
      {f->first_device_id >= 0, "--first-device-id", ">= 0"},
      {f->interval_s == 0.0 || (f->interval_s >= 0.1 && f->interval_s <= hapsim::common::kMaxFlagSeconds),
       "--interval-s", "0 (off) or [0.1, 1e7]"},
  });
  if (!out_of_range.empty()) {
    std::fprintf(stderr, "hapsim-load: %s\n", out_of_range.c_str());
    return false;
  }
  if (!f->intervals_csv_file.empty() && f->interval_s == 0.0) {
    std::fprintf(stderr, "hapsim-load: --intervals-csv needs --interval-s (the length of an interval)\n");
    return false;
  }
  if (std::string error; !hapsim::viewer::FinishConnectionFlags(f->connection_flags, &f->connection, &error)) {
    std::fprintf(stderr, "hapsim-load: %s\n", error.c_str());
    return false;
  }
  if (const std::string bad = hapsim::bridge::CheckSceneParams(f->params); !bad.empty()) {
    std::fprintf(stderr, "hapsim-load: %s\n", bad.c_str());
    return false;
  }
  return true;
}

// The devices and the run; false (after saying why) if the script or the
// safety settings are wrong.
bool PlanLoad(LoadFlags* f, std::vector<hapsim::bridge::LoadDevicePlan>* plan,
              hapsim::bridge::LoadRunConfig* run_config) {
  try {
    f->plan_options.devices = f->devices;
    f->plan_options.sessions = hapsim::bridge::SplitCommaList(f->sessions);
    f->plan_options.first_device_id = static_cast<std::uint32_t>(f->first_device_id);
    f->plan_options.period_s = 1.0 / f->rate_hz;
    f->plan_options.script = f->script.ToScript();
    hapsim::bridge::ValidateSyntheticScript(f->plan_options.script);
    *plan = hapsim::bridge::PlanDevices(f->plan_options);
    run_config->safety = f->safety.ToConfig();
    run_config->pose_deadband = f->pose_deadband.ToConfig();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-load: %s\n", e.what());
    return false;
  }
  run_config->rate_hz = f->rate_hz;
  run_config->run_seconds = f->seconds;
  run_config->interval_s = f->interval_s;
  return true;
}

// --create: false (after saying why) if a session could not be created.
bool CreateLoadSessions(const LoadFlags& f, hapsim::viewer::SessionClient& client,
                        const std::vector<hapsim::bridge::LoadDevicePlan>& plan, CloseSessionsAtExit* close_at_exit) {
  std::vector<std::string> created;
  const std::string create_error = hapsim::bridge::CreateSessions(client, plan, {f.create_scene, f.params}, &created);
  if (!create_error.empty()) {
    std::fprintf(stderr, "hapsim-load: cannot create sessions at %s: %s\n", f.connection.address.c_str(),
                 create_error.c_str());
    return false;
  }
  spdlog::info("created {} sessions of {} at {}", created.size(), f.create_scene, f.connection.address);
  if (!f.keep_sessions) {
    close_at_exit->client = &client;
    close_at_exit->ids = created;
  }
  return true;
}

hapsim::bridge::LoadReport RunDevicesUntilStopped(const LoadFlags& f, hapsim::bridge::LoadRunner& runner,
                                                  const std::vector<hapsim::bridge::LoadDevicePlan>& plan) {
  std::atomic<bool> stop{false};
  hapsim::bridge::StopOnSignal stop_on_signal(&stop);
  spdlog::info("{} devices (ids {}..{}), script {}, at {} Hz", plan.size(), plan.front().device_id,
               plan.back().device_id, f.script.kind, f.rate_hz);
  hapsim::bridge::RaiseServoPath(f.process.rt_priority);  // this thread is the servo thread
  return runner.Run(stop);
}

// --json, --csv, --intervals-csv; 1 if one could not be written, else 0.
int WriteLoadSummaries(const LoadFlags& f, const hapsim::bridge::LoadReport& report) {
  int rc = 0;
  if (!f.json_file.empty() && !hapsim::bridge::WriteTextFile(f.json_file, hapsim::bridge::FormatLoadJson(report))) {
    std::fprintf(stderr, "hapsim-load: cannot write %s\n", f.json_file.c_str());
    rc = 1;
  }
  if (!f.csv_file.empty() && !hapsim::bridge::WriteTextFile(f.csv_file, hapsim::bridge::FormatLoadCsv(report))) {
    std::fprintf(stderr, "hapsim-load: cannot write %s\n", f.csv_file.c_str());
    rc = 1;
  }
  if (!f.intervals_csv_file.empty() &&
      !hapsim::bridge::WriteTextFile(f.intervals_csv_file, hapsim::bridge::FormatLoadIntervalsCsv(report))) {
    std::fprintf(stderr, "hapsim-load: cannot write %s\n", f.intervals_csv_file.c_str());
    rc = 1;
  }
  return rc;
}

// After the run: the server's statistics, closing the sessions, DDS teardown.
constexpr double kTeardownLimitS = 15.0;

// The run, the table on stdout and the summaries; the process's exit code.
int RunLoad(const LoadFlags& f, const std::vector<hapsim::bridge::LoadDevicePlan>& plan,
            const hapsim::bridge::LoadRunConfig& run_config) {
  std::vector<std::string> session_ids;
  for (const auto& d : plan) session_ids.push_back(d.session);
  // Outlives the DDS participant, whose deletion can block for good when the
  // network interface has vanished (shutdown_deadline.h).
  hapsim::common::ShutdownDeadline deadline("hapsim-load");
  try {
    hapsim::viewer::SessionClient client(f.connection);  // throws on unreadable TLS files
    CloseSessionsAtExit close_at_exit;                   // declared after the client: runs first
    hapsim::bridge::ModelRouter router(plan.front().device_id, session_ids);
    hapsim::bridge::DeviceDds dds(f.process.Dds(), &router);
    hapsim::bridge::LoadRunner runner(plan, run_config, &router,
                                      [&dds](const hapsim::bridge::SensedPose& pose) { return dds.WritePose(pose); });
    spdlog::info("DDS domain {} with config: {}", f.process.dds_domain, dds.config_origin());
    if (!f.create_scene.empty() && !CreateLoadSessions(f, client, plan, &close_at_exit)) return 1;

    dds.Start();
    hapsim::bridge::LoadReport report = RunDevicesUntilStopped(f, runner, plan);
    // What is left: the server's statistics and closing the sessions (gRPC, with deadlines), DDS teardown.
    deadline.Arm(kTeardownLimitS);
    dds.Stop();
    if (!f.create_scene.empty() || f.server_stats) report.server = hapsim::bridge::FetchServerStats(client, plan);

    std::fputs(hapsim::bridge::FormatLoadTable(report).c_str(), stdout);
    std::fflush(stdout);
    deadline.set_exit_code(WriteLoadSummaries(f, report));
    return deadline.exit_code();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-load: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  LoadFlags f;
  hapsim::common::Flags flags("hapsim-load", kSummary);
  AddLoadFlags(flags, &f);
  const int parse_exit = hapsim::bridge::ParseCommandLine(flags, argc, argv, f.process, "hapsim-load", "load");
  if (parse_exit >= 0) return parse_exit;
  if (!CheckLoadFlags(&f)) return 2;
  std::vector<hapsim::bridge::LoadDevicePlan> plan;
  hapsim::bridge::LoadRunConfig run_config;
  if (!PlanLoad(&f, &plan, &run_config)) return 2;
  return RunLoad(f, plan, run_config);
}
