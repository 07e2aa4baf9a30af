// hapsim-ctl: the session-control RPCs from a shell — what an instructor's
// panel does: list/create/close sessions, pause/resume/reset, export a mesh
// snapshot, submit and read scores, check server health.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "ctl_commands.h"
#include "hapsim/common/flags.h"
#include "hapsim/viewer/connection.h"
#include "hapsim/viewer/session_locator.h"

namespace {

// The help's summary: what the tool does and its commands (the flags follow, listed by Flags).
constexpr const char* kUsage =
    "Session control for a hapsim-server (default server 127.0.0.1:50051; every call gives up\n"
    "after --timeout-s seconds, default 10). A server with a class config wants a token: --token,\n"
    "--token-file or the HAPSIM_TOKEN environment variable (docs/classroom.md).\n\ncommands:\n"
    "  scenes                              the scenes a session can run, with every parameter\n"
    "  list                                list sessions with their counters\n"
    "  create [ID | --id ID] [--scene NAME] [--owner NAME] [--param KEY=VALUE]...\n"
    "                                      create a session (prints its id)\n"
    "  info ID | close ID | pause ID | resume ID | reset ID\n"
    "  snapshot ID --obj FILE | --export FILE\n"
    "                                      write the session's current mesh (full precision): OBJ, or by\n"
    "                                      extension .obj, .gltf/.glb (glTF 2.0), .vtk (legacy VTK)\n"
    "  score ID --indicators a,b,c,d,e,f,g [--expert NAME]\n"
    "                                      submit 7 indicator scores (0..10) for a session\n"
    "  scores [ID]                         comprehensive scores of one session or the whole class\n"
    "  join ID                             the DDS partition and domain a device of session ID streams on\n"
    "  locate ID                           which server of the site runs session ID (servers with --directory;\n"
    "                                      commands on a session go to that server by themselves)\n"
    "  watch [CLASS] [--rate-hz R] [--count N]\n"
    "                                      live table of every session of CLASS (like top; no CLASS: every\n"
    "                                      session of a server without a class config); --count: stop after N\n"
    "  push CLASS [--scene NAME] [--param KEY=VALUE]...\n"
    "                                      restart every session of CLASS with this scene (same ids, trainees)\n"
    "  trials [CLASS] [--csv FILE]          every trial's automatic metrics (depth error, layers, peak forces,\n"
    "                                      incision, line deviation, score) as CSV, to stdout or FILE\n"
    "  recordings [SESSION]                the trial recordings the caller may see (server with --data-dir)\n"
    "  fetch-recording ID [--output FILE]  download one, to replay with `hapsim-replay FILE`\n"
    "  delete-recording ID                 delete one (instructors; not a running trial's)\n"
    "  replay ID [--speed X] [--start-s S] [--paused]\n"
    "                                      replay a recording as a session viewers watch (prints its id)\n"
    "  replay-info SESSION | step SESSION [--ticks N] | seek SESSION --to-s S\n"
    "                                      where a replay is and whether it matches its recorded hashes;\n"
    "                                      play N ticks while paused; go to another moment of the trial\n"
    "  health                              gRPC health check (exit 0 when SERVING)\n"
    "`hapsim-ctl COMMAND --help` lists a command's own flags.";

using hapsim::ctl::CommandCall;
using hapsim::ctl::IdArg;
using FlagsResult = hapsim::common::Flags::Result;

constexpr int kGoOn = -1;  // a parsing step's "no exit yet"

struct GlobalFlags {
  hapsim::viewer::Connection connection;
  hapsim::viewer::ConnectionFlags connection_flags;
  double timeout_s = 10.0;
};

// The global flags up to the command: kGoOn with *command_at its index, or the exit code.
int ParseGlobalFlags(int argc, char** argv, hapsim::common::Flags* flags, int* command_at, const GlobalFlags& g) {
  std::string error;
  switch (flags->Parse(argc, argv, &error, command_at)) {
    case FlagsResult::kHelp:
      std::fputs(flags->Help().c_str(), stdout);
      return 0;
    case FlagsResult::kVersion:
      std::fputs(flags->Version().c_str(), stdout);
      return 0;
    case FlagsResult::kError:
      std::fprintf(stderr, "hapsim-ctl: %s\n", error.c_str());
      return 2;
    case FlagsResult::kOk:
      break;
  }
  if (const std::string bad = hapsim::common::FirstFlagOutOfRange(
          {{g.timeout_s > 0.0 && g.timeout_s <= 3600.0, "--timeout-s", "(0, 3600]"}});
      !bad.empty()) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", bad.c_str());
    return 2;
  }
  if (*command_at >= argc) {
    std::fputs(flags->Help().c_str(), stderr);
    return 2;
  }
  return kGoOn;
}

// No id where none is taken, at most one, and one where it is needed.
int CheckIds(const std::string& command, IdArg id_arg, const std::vector<std::string>& ids) {
  if (id_arg == IdArg::kNone && !ids.empty()) {
    std::fprintf(stderr, "hapsim-ctl %s: takes no id, got '%s'\n", command.c_str(), ids[0].c_str());
    return 2;
  }
  if (ids.size() > 1) {
    std::fprintf(stderr, "hapsim-ctl %s: takes one id, got '%s' and '%s'\n", command.c_str(), ids[0].c_str(),
                 ids[1].c_str());
    return 2;
  }
  if (id_arg == IdArg::kOneId && ids.empty()) {
    std::fprintf(stderr, "hapsim-ctl: %s needs a %s\n", command.c_str(),
                 command == "push"                                ? "class name"
                 : command.find("recording") != std::string::npos ? "recording id"
                                                                  : "session id");
    return 2;
  }
  return kGoOn;
}

// The command's own flags and id (argv[0] is the command): kGoOn with
// call->flags and call->id set, or the exit code.
int ParseCommand(int argc, char** argv, IdArg id_arg, const std::string& version, CommandCall* call) {
  const std::string& command = call->command;
  hapsim::common::Flags flags("hapsim-ctl " + command, "One command of hapsim-ctl (hapsim-ctl --help lists them).",
                              id_arg == IdArg::kNone    ? "[flags]"
                              : id_arg == IdArg::kOneId ? "ID [flags]"
                                                        : "[ID] [flags]");
  hapsim::ctl::AddCommandFlags(command, &flags, &call->flags);
  std::vector<std::string> ids;
  flags.AllowPositionals(&ids);
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case FlagsResult::kHelp:
      std::fputs(flags.Help().c_str(), stdout);
      return 0;
    case FlagsResult::kVersion:
      std::fputs(version.c_str(), stdout);
      return 0;
    case FlagsResult::kError:
      if (const auto at = error.find("see --help"); at != std::string::npos) {
        error.replace(at, 10, "see hapsim-ctl " + command + " --help");
      }
      std::fprintf(stderr, "hapsim-ctl %s: %s\n", command.c_str(), error.c_str());
      return 2;
    case FlagsResult::kOk:
      break;
  }
  if (const int exit_code = CheckIds(command, id_arg, ids); exit_code != kGoOn) return exit_code;
  call->id = ids.empty() ? "" : ids[0];
  return kGoOn;
}

// For a command on a session: the server that hosts it, if the asked
// server's directory names another (kGoOn), or the exit code.
int FollowSession(const std::string& session_id, GlobalFlags& g) {
  const auto location = hapsim::viewer::LocateSession(g.connection, session_id, g.timeout_s, /*wait_for_server=*/false);
  if (hapsim::viewer::LocateStopsTheClient(location)) return hapsim::ctl::ReportFailure(location.status);
  if (location.moved) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", hapsim::viewer::DescribeLocation(location).c_str());
    g.connection = location.connection;
  }
  return kGoOn;
}

// The channel, stub and the call's context (token, --timeout-s deadline): kGoOn or the exit code.
int OpenCall(GlobalFlags& g, bool follows_session, CommandCall* call) {
  std::string error;
  if (!hapsim::viewer::FinishConnectionFlags(g.connection_flags, &g.connection, &error)) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", error.c_str());
    return 2;
  }
  try {
    if (follows_session) {
      if (const int exit_code = FollowSession(call->id, g); exit_code != kGoOn) return exit_code;
    }
    call->channel = hapsim::viewer::MakeChannel(g.connection);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hapsim-ctl: %s\n", e.what());
    return 2;
  }
  call->stub = hapsim::v1::SessionService::NewStub(call->channel);
  call->token = g.connection.token;
  hapsim::viewer::AddToken(&call->context, call->token);
  call->context.set_deadline(
      std::chrono::system_clock::now() +
      std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(g.timeout_s)));
  return kGoOn;
}

}  // namespace

int main(int argc, char** argv) {
  GlobalFlags g;
  hapsim::common::Flags flags("hapsim-ctl", kUsage, "[flags] COMMAND [ID] [command flags]");
  flags.Add("server", &g.connection.address, "server address HOST:PORT");
  flags.Add("timeout-s", &g.timeout_s, "every call gives up after this long [s], (0, 3600]");
  hapsim::viewer::AddConnectionFlags(&flags, &g.connection, &g.connection_flags);
  int command_at = argc;
  if (const int exit_code = ParseGlobalFlags(argc, argv, &flags, &command_at, g); exit_code != kGoOn) return exit_code;
  CommandCall call;
  call.command = argv[command_at];
  const hapsim::ctl::Command* command = hapsim::ctl::FindCommand(call.command);
  if (!command) {
    std::fprintf(stderr, "hapsim-ctl: unknown command '%s' (see hapsim-ctl --help)\n", call.command.c_str());
    return 2;
  }
  if (const int exit_code = ParseCommand(argc - command_at, argv + command_at, command->id, flags.Version(), &call);
      exit_code != kGoOn) {
    return exit_code;
  }
  if (const int exit_code = OpenCall(g, command->follows_session, &call); exit_code != kGoOn) return exit_code;
  return command->run(call);
}
