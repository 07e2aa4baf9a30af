// hapsim-server: the physics server. Hosts sessions (one scene each, ticked
// at 1 kHz on a worker pool, clocked by their devices' poses), takes device
// poses over DDS, answers with local force models,
// and streams mesh frames to viewers over gRPC. SIGINT/SIGTERM stop it
// cleanly; a one-line-per-session summary goes to stdout at exit.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/signal_set.hpp>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "hapsim/app/server_app.h"
#include "hapsim/common/flags.h"
#include "hapsim/common/idle_wait.h"
#include "hapsim/common/logging.h"
#include "hapsim/common/shutdown_deadline.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/core/scenes/scene.h"

namespace {

// "--sessions demo:tissue_block,s2:acupuncture" -> sessions created at start.
bool CreateStartupSessions(hapsim::service::SessionRegistry& registry, const std::string& list) {
  std::stringstream items(list);
  std::string item;
  while (std::getline(items, item, ',')) {
    if (item.empty()) continue;
    const auto colon = item.find(':');
    const std::string id = item.substr(0, colon);
    const std::string scene = colon == std::string::npos ? "tissue_block" : item.substr(colon + 1);
    if (registry.Find(id)) {  // brought back from the data directory
      spdlog::info("session '{}' of --sessions runs already (brought back from the data directory)", id);
      continue;
    }
    try {
      registry.Create(id, scene, "", {});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hapsim-server: cannot create session '%s': %s\n", id.c_str(), e.what());
      return false;
    }
  }
  return true;
}

void PrintSummary(hapsim::service::ServerApp& app) {
  const auto& d = app.dds().counters();
  const auto pool = app.pool().stats();
  std::printf("server: poses accepted %llu, rejected %llu, wrong-session %llu, other-device %llu, stale %llu; "
              "force models written %llu; tick pool %d workers, %llu ticks, %llu wake-ups\n",
              static_cast<unsigned long long>(d.poses_accepted.load()),
              static_cast<unsigned long long>(d.poses_rejected.load()),
              static_cast<unsigned long long>(d.poses_wrong_session.load()),
              static_cast<unsigned long long>(d.poses_other_device.load()),
              static_cast<unsigned long long>(d.poses_stale.load()),
              static_cast<unsigned long long>(d.force_models_written.load()), app.pool().workers(),
              static_cast<unsigned long long>(pool.ticks), static_cast<unsigned long long>(pool.wakeups));
  for (const auto& s : app.registry().List()) {
    const auto& c = s->counters();
    std::printf(
        "session %s (%s): ticks %llu (device-clocked %llu), poses unused %llu, sim %.3f s, late ticks %llu "
        "(worst %.3f ms late), peak tool force %.3f N, numerical resets %llu\n",
        s->id().c_str(), s->config().scene.c_str(), static_cast<unsigned long long>(c.tick.ticks.load()),
        static_cast<unsigned long long>(c.tick.device_clocked_ticks.load()),
        static_cast<unsigned long long>(c.tick.poses_unused.load()), c.tick.sim_time_s.load(),
        static_cast<unsigned long long>(c.tick.late_ticks.load()),
        static_cast<double>(c.tick.max_lateness_ns.load()) * 1e-6, c.tick.peak_tool_force_N.load(),
        static_cast<unsigned long long>(c.tick.numerical_resets.load()));
  }
  std::fflush(stdout);
}

// --help: the flags, then every scene with its parameters (from the scenes'
// parameter tables, as ListScenes and `hapsim-ctl scenes` give them).
void PrintHelp(const hapsim::common::Flags& flags) {
  std::fputs(flags.Help().c_str(), stdout);
  std::printf("\nScenes (--sessions id:scene uses the defaults; `hapsim-ctl create --param KEY=VALUE` sets them):\n");
  for (const auto& scene : hapsim::core::SceneCatalog()) {
    std::printf("\n%s: %s\n%s", scene.name.c_str(), scene.description.c_str(),
                hapsim::core::FormatParams(scene.params).c_str());
  }
}

// This machine's name: the default --server-name (a StatefulSet pod's name is its hostname).
std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return "hapsim-server";
  return name;
}

// The web app next to this program: PREFIX/share/hapsim/web for
// PREFIX/bin/hapsim-server, installed or in the build tree (build/bin, build/share).
std::string DefaultWebRoot() {
  char exe[4096] = {};
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return "/usr/share/hapsim/web";
  std::string path(exe, static_cast<std::size_t>(n));
  path.erase(path.rfind('/'));      // .../bin
  path.erase(path.rfind('/') + 1);  // .../
  return path + "share/hapsim/web";
}

// Flags that ServerOptions holds in other units, or that only main uses.
struct ServerFlags {
  std::string log_level = "info", sessions, dds_config, port_file, class_config, data_dir, record = "class";
  std::string directory, server_name = HostName(), peer_tls_ca;
  std::string tick_cpus;
  std::string dds_io_scheduling = "batch";
  std::string tick_wait = "sleep";
  double peer_timeout_ms = 1000.0;
  double recording_flush_ms = 50.0, recording_fsync_ms = 0.0, checkpoint_every_s = 1.0, retention_days = 90.0;
  bool database_fsync = false;
  double tick_hz = 1000.0, quantum_mm = 0.01, pose_timeout_ms = 250.0, pose_slack_ms = 0.5;
  double pose_extrapolation_ms = 100.0, model_deadband = 0.07, model_keepalive_ms = 25.0;
  int dds_domain = 0, max_sessions = 64;
};

// In the order --help lists them.
void AddServerFlags(hapsim::common::Flags& flags, hapsim::service::ServerOptions* options, ServerFlags* f) {
  flags.Add("listen", &options->listen_address, "gRPC listen address (host:port; port 0 picks a free one)");
  flags.Add("port-file", &f->port_file, "write the bound gRPC port here once listening (for scripts using port 0)");
  flags.Add("metrics-listen", &options->metrics_listen_address,
            "serve Prometheus metrics at http://HOST:PORT/metrics (docs/metrics.md; empty: off)");
  flags.Add("web-listen", &options->web_listen_address,
            "serve the browser console at https://HOST:PORT/ (http:// without --tls-cert; docs/classroom.md).\n"
            "Empty: off");
  flags.Add("web-root", &options->web_root,
            "the built web app the console serves (PREFIX/share/hapsim/web beside the program)");
  flags.Add("sessions", &f->sessions, "sessions to create at start: id[:scene],id[:scene],...");
  flags.Add("class-config", &f->class_config,
            "TOML file of classes, their sessions (created at start) and tokens with roles (docs/classroom.md);\n"
            "every call then needs a token. Empty: development mode, no tokens (keep --listen on loopback)");
  flags.Add("tls-cert", &options->tls_cert_file, "serve gRPC over TLS with this PEM certificate (chain)");
  flags.Add("tls-key", &options->tls_key_file, "the PEM private key of --tls-cert");
  flags.Add("tls-client-ca", &options->tls_client_ca_file,
            "require client certificates signed by this PEM CA (with --tls-cert/--tls-key)");
  flags.Add("directory", &f->directory,
            "TOML file of the site's servers ([[server]] name, address; docs/deploy.md): Locate then finds\n"
            "sessions on the other servers too. Empty: this server answers for its own sessions only");
  flags.Add("server-name", &f->server_name, "this server's name in --directory (default: the host name)");
  flags.Add("peer-tls-ca", &f->peer_tls_ca, "dial the directory's other servers over TLS, trusting this PEM CA");
  flags.Add("peer-timeout-ms", &f->peer_timeout_ms,
            "a server of the directory that has not answered a Locate by then counts as unreachable [ms]");
  flags.Add("data-dir", &f->data_dir,
            "keep trials, scores, trial recordings and the live sessions here, and bring them back at start\n"
            "(docs/recording.md). Empty: nothing outlives the process");
  flags.Add("record", &f->record,
            "with --data-dir, whose trials are recorded: class (the class config's sessions), all, none");
  flags.Add("recording-flush-ms", &f->recording_flush_ms,
            "recorded ticks reach the OS at least this often: what a crash of the server can lose [ms]");
  flags.Add("recording-fsync-ms", &f->recording_fsync_ms,
            "also fsync recordings this often, so a power loss loses at most this much [ms] (0: never)");
  flags.Add("checkpoint-every-s", &f->checkpoint_every_s,
            "a recorded state hash every this much of a trial [s] (a replay is checked at each)");
  flags.Add("retention-days", &f->retention_days, "delete closed recordings older than this [days] (0: keep all)");
  flags.Add("database-fsync", &f->database_fsync,
            "commit the results database with a full fsync (survives a power loss; slower)");
  flags.Add("tick-hz", &f->tick_hz, "physics tick rate of every session [Hz]");
  flags.Add("frame-rate-hz", &options->sessions.frame_rate_hz, "viewer frame rate [Hz]");
  flags.Add("max-sessions", &f->max_sessions, "refuse to create more sessions than this");
  flags.Add("quantum-mm", &f->quantum_mm, "position quantisation of viewer deltas [mm]");
  flags.Add("pose-timeout-ms", &f->pose_timeout_ms, "no pose for this long: the tool counts as absent [ms]");
  flags.Add("pose-slack-ms", &f->pose_slack_ms,
            "a device's pose clocks its session; a pose later than one period plus this: tick without it [ms]");
  flags.Add("pose-extrapolation-ms", &f->pose_extrapolation_ms,
            "between poses, move the tool along its last velocity for at most this long, then hold it [ms]");
  flags.Add("model-deadband", &f->model_deadband,
            "send a force model only when the device would feel the change: this fraction of the force\n"
            "(Weber; 0.07 is the force JND), else as a keep-alive (docs/deploy.md). 0: every tick");
  flags.Add("model-keepalive-ms", &f->model_keepalive_ms,
            "with --model-deadband: an unchanged model still goes out this often [ms]");
  flags.Add("workers", &options->workers, "tick worker threads (0: one per CPU this process may run on)");
  flags.Add("rt-priority", &options->rt_priority,
            "run the tick workers at this SCHED_FIFO priority and the pose receive threads one above, so\n"
            "viewers, gRPC and recording never delay a tick (needs CAP_SYS_NICE or LimitRTPRIO; refused:\n"
            "a warning, normal priority). 0: normal scheduling");
  flags.Add("tick-cpus", &f->tick_cpus,
            "CPUs of the 1 kHz path, e.g. 0 or 2-3: the tick workers and pose receive threads run only\n"
            "there, every other thread (gRPC, viewers, web console, recording) only on the other CPUs; the\n"
            "tick pool defaults to one worker per tick CPU. Empty: no pinning");
  flags.Add("tick-wait", &f->tick_wait,
            "sleep or spin: between ticks a worker sleeps, or polls the clock yielding to other threads so its\n"
            "CPU never idles (on a VM an idle CPU can be woken late; docs/deploy.md). spin keeps one CPU per\n"
            "worker busy: for CPUs given to the 1 kHz path. Not with --rt-priority");
  flags.Add("dds-io-scheduling", &f->dds_io_scheduling,
            "batch or normal: the thread that routes poses to sessions waits for DDS's receive thread to\n"
            "finish (batch: fewer context switches per pose) or preempts it (normal). Moot with --rt-priority");
  flags.Add("max-message-bytes", &options->max_message_bytes, "largest gRPC request accepted [bytes]");
  flags.Add("dds-domain", &f->dds_domain, "DDS domain id");
  flags.Add("dds-config", &f->dds_config,
            "Cyclone DDS config file (default: CYCLONEDDS_URI if set, else the built-in loopback config)");
  flags.Add("log-level", &f->log_level, "trace, debug, info, warn, error or off");
}

// The exit code if the command line ends the run (--help, --version, a bad
// flag), else -1.
int ParseResultExitCode(const hapsim::common::Flags& flags, hapsim::common::Flags::Result result,
                        const std::string& error) {
  switch (result) {
    case hapsim::common::Flags::Result::kHelp: PrintHelp(flags); return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::fputs(flags.Version().c_str(), stdout);
      return 0;
    case hapsim::common::Flags::Result::kError: std::fprintf(stderr, "hapsim-server: %s\n", error.c_str()); return 2;
    case hapsim::common::Flags::Result::kOk: break;
  }
  return -1;
}

// False (after saying which) if a flag is out of its range.
bool ServerFlagsInRange(const ServerFlags& f, const hapsim::service::ServerOptions& options) {
  if (!(f.tick_hz >= 10.0 && f.tick_hz <= 10000.0)) {
    std::fprintf(stderr, "hapsim-server: --tick-hz must be within [10, 10000]\n");
    return false;
  }
  // Each flag's range, named in the message (a bad value must not surface
  // later as a client's error).
  const std::string out_of_range = hapsim::common::FirstFlagOutOfRange({
      {f.quantum_mm > 0.0 && f.quantum_mm <= 1.0, "--quantum-mm", "(0, 1]"},
      {f.max_sessions >= 1, "--max-sessions", ">= 1"},
      {f.dds_domain >= 0 && f.dds_domain <= 232, "--dds-domain", "[0, 232]"},
      {f.pose_timeout_ms > 0.0 && f.pose_timeout_ms <= 60000.0, "--pose-timeout-ms", "(0, 60000]"},
      {f.pose_slack_ms >= 0.0 && f.pose_slack_ms <= f.pose_timeout_ms, "--pose-slack-ms", "[0, --pose-timeout-ms]"},
      {f.pose_extrapolation_ms >= 0.0 && f.pose_extrapolation_ms <= f.pose_timeout_ms, "--pose-extrapolation-ms",
       "[0, --pose-timeout-ms]"},
      {f.model_deadband >= 0.0 && f.model_deadband <= 1.0, "--model-deadband", "[0, 1]"},
      {f.model_keepalive_ms > 0.0 && f.model_keepalive_ms <= f.pose_timeout_ms, "--model-keepalive-ms",
       "(0, --pose-timeout-ms]"},
      {options.workers >= 0 && options.workers <= 64, "--workers", "[0, 64]"},
      {options.rt_priority >= 0 && options.rt_priority <= 98, "--rt-priority", "[0, 98]"},
      {f.recording_flush_ms >= 1.0 && f.recording_flush_ms <= 10000.0, "--recording-flush-ms", "[1, 10000]"},
      {f.recording_fsync_ms >= 0.0 && f.recording_fsync_ms <= 3.6e6, "--recording-fsync-ms", "[0, 3600000]"},
      {f.checkpoint_every_s >= 0.001 && f.checkpoint_every_s <= 600.0, "--checkpoint-every-s", "[0.001, 600]"},
      {f.retention_days >= 0.0 && f.retention_days <= 36500.0, "--retention-days", "[0, 36500]"},
      {options.max_message_bytes >= 1024, "--max-message-bytes", ">= 1024"},
      {f.peer_timeout_ms >= 10.0 && f.peer_timeout_ms <= 60000.0, "--peer-timeout-ms", "[10, 60000]"},
      {options.sessions.frame_rate_hz > 0.0 && options.sessions.frame_rate_hz <= 1000.0, "--frame-rate-hz",
       "(0, 1000]"},
  });
  if (!out_of_range.empty()) {
    std::fprintf(stderr, "hapsim-server: %s\n", out_of_range.c_str());
    return false;
  }
  return true;
}

// The flags into options, in SI units; false (after saying why) if the
// class config cannot be used.
bool ApplyServerFlags(const ServerFlags& f, hapsim::service::ServerOptions* options) {
  if (!f.tick_cpus.empty()) {
    const auto cpus = hapsim::common::ParseCpuList(f.tick_cpus);
    const std::string why =
        !cpus ? "\"" + f.tick_cpus + "\" is not a CPU list like 0, 0,2 or 2-3" : hapsim::common::CheckTickCpus(*cpus);
    if (!why.empty()) {
      std::fprintf(stderr, "hapsim-server: --tick-cpus: %s\n", why.c_str());
      return false;
    }
    options->tick_cpus = *cpus;
  }
  if (f.dds_io_scheduling != "batch" && f.dds_io_scheduling != "normal") {
    std::fprintf(stderr, "hapsim-server: --dds-io-scheduling: \"%s\" is neither batch nor normal\n",
                 f.dds_io_scheduling.c_str());
    return false;
  }
  options->dds_io_scheduling = f.dds_io_scheduling == "batch" ? hapsim::dds::IoThread::Scheduling::kBatch
                                                              : hapsim::dds::IoThread::Scheduling::kNormal;
  const auto tick_wait = hapsim::common::ParseIdleWait(f.tick_wait);
  if (!tick_wait) {
    std::fprintf(stderr, "hapsim-server: --tick-wait: \"%s\" is neither sleep nor spin\n", f.tick_wait.c_str());
    return false;
  }
  options->tick_wait = *tick_wait;
  // A real-time thread that never sleeps is throttled by the kernel (by
  // default 50 ms of every second, sched_rt_runtime_us): every tick stops.
  if (options->tick_wait == hapsim::common::IdleWait::kSpin && options->rt_priority > 0) {
    std::fprintf(stderr,
                 "hapsim-server: --tick-wait spin and --rt-priority exclude each other: the kernel stops a real-time "
                 "thread that never sleeps for 50 ms of every second (sched_rt_runtime_us)\n");
    return false;
  }
  options->sessions.tick_period_s = 1.0 / f.tick_hz;
  options->sessions.max_sessions = static_cast<std::size_t>(f.max_sessions);
  options->sessions.pose_timeout_s = f.pose_timeout_ms * 1e-3;
  options->sessions.pose_slack_s = f.pose_slack_ms * 1e-3;
  options->sessions.pose_extrapolation_s = f.pose_extrapolation_ms * 1e-3;
  options->sessions.model_deadband.jnd = f.model_deadband;
  options->sessions.model_deadband.keepalive_s = f.model_keepalive_ms * 1e-3;
  options->quantum_m = f.quantum_mm * 1e-3;
  options->dds.domain_id = static_cast<std::uint32_t>(f.dds_domain);
  options->dds.config_file = f.dds_config;
  if (!options->web_listen_address.empty() && access((options->web_root + "/index.html").c_str(), R_OK) != 0) {
    std::fprintf(stderr,
                 "hapsim-server: no web app in '%s' (no index.html): build it (cmake --build with npm installed)\n"
                 "or give --web-root\n",
                 options->web_root.c_str());
    return false;
  }
  if (!f.data_dir.empty()) {
    hapsim::service::PersistenceOptions p;
    p.data_dir = f.data_dir;
    if (!hapsim::service::ParseRecordPolicy(f.record, &p.record)) {
      std::fprintf(stderr, "hapsim-server: --record must be class, all or none (not '%s')\n", f.record.c_str());
      return false;
    }
    p.recording.flush_interval_ms = static_cast<std::int64_t>(f.recording_flush_ms);
    p.recording.fsync_interval_ms = static_cast<std::int64_t>(f.recording_fsync_ms);
    p.recording.checkpoint_every_ticks =
        static_cast<std::uint32_t>(std::max(1.0, std::round(f.checkpoint_every_s * f.tick_hz)));
    p.retention_days = f.retention_days;
    p.fsync_database = f.database_fsync;
    options->persistence = p;
  }
  if (!f.directory.empty()) {
    hapsim::service::DirectoryOptions d;
    try {
      d.directory = hapsim::service::LoadServerDirectory(f.directory);
    } catch (const hapsim::service::ClassConfigError& e) {
      std::fprintf(stderr, "hapsim-server: bad --directory: %s\n", e.what());
      return false;
    }
    d.server_name = f.server_name;
    d.peer_tls_ca_file = f.peer_tls_ca;
    d.peer_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(f.peer_timeout_ms));
    options->directory = std::move(d);
  } else if (!f.peer_tls_ca.empty()) {
    std::fprintf(stderr, "hapsim-server: --peer-tls-ca needs --directory\n");
    return false;
  }
  if (!f.class_config.empty()) {
    try {
      options->classes = hapsim::service::LoadClassConfig(f.class_config);
    } catch (const hapsim::service::ClassConfigError& e) {
      std::fprintf(stderr, "hapsim-server: bad --class-config: %s\n", e.what());
      return false;
    }
  }
  return true;
}

bool WritePortFile(const std::string& port_file, int port) {
  std::FILE* f = std::fopen(port_file.c_str(), "w");
  if (!f || std::fprintf(f, "%d\n", port) < 0 || std::fclose(f) != 0) {
    std::fprintf(stderr, "hapsim-server: cannot write --port-file %s\n", port_file.c_str());
    return false;
  }
  return true;
}

void WaitForStopSignal() {
  asio::io_context io;
  asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait(
      [&](const std::error_code&, int signal) { spdlog::info("signal {} received: shutting down", signal); });
  io.run();  // returns once the signal handler has run
}

// Shutdown normally takes well under a second, at most the 2 s gRPC gives its calls.
constexpr double kTeardownLimitS = 5.0;

// Serves until SIGINT/SIGTERM; the process's exit code.
int RunServer(const hapsim::service::ServerOptions& options, const ServerFlags& f) {
  // Outlives the app: its DDS participant's deletion can block for good when
  // the network interface has vanished (shutdown_deadline.h).
  hapsim::common::ShutdownDeadline deadline("hapsim-server");
  try {
    hapsim::service::ServerApp app(options);
    if (!CreateStartupSessions(app.registry(), f.sessions)) return 2;
    // Written after the sessions exist, so a script that sees the file can use them.
    if (!f.port_file.empty() && !WritePortFile(f.port_file, app.bound_port())) return 1;
    WaitForStopSignal();
    // gRPC gets 2 s to end its calls; sessions and DDS follow.
    deadline.Arm(kTeardownLimitS);
    PrintSummary(app);
    app.Shutdown();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-server: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hapsim::service::ServerOptions options;
  options.web_root = DefaultWebRoot();
  ServerFlags f;
  hapsim::common::Flags flags(
      "hapsim-server",
      "Physics server of hapsim: runs tissue-simulation sessions at a fixed tick rate, takes stylus\n"
      "poses over DDS, answers each with a local force model, and streams mesh frames to viewers\n"
      "over gRPC (SessionService, ViewerService, health checking).");
  AddServerFlags(flags, &options, &f);
  std::string error;
  const auto parsed = flags.Parse(argc, argv, &error);
  if (const int exit_code = ParseResultExitCode(flags, parsed, error); exit_code >= 0) return exit_code;
  if (!ServerFlagsInRange(f, options)) return 2;
  if (!hapsim::common::SetUpLogging("server", f.log_level)) {
    std::fprintf(stderr, "hapsim-server: unknown --log-level '%s'\n", f.log_level.c_str());
    return 2;
  }
  if (!ApplyServerFlags(f, &options)) return 2;
  return RunServer(options, f);
}
