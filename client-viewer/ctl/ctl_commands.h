// hapsim-ctl's commands: each a function that makes its call, prints the
// answer and returns the exit code (0; 1 when the server refuses or a file
// cannot be written; 2 for bad use), found by name in one table.
#pragma once
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>
#include <vector>

#include "hapsim/common/flags.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::ctl {

// A command's own flags (all optional strings; each command checks what it needs).
struct CommandFlags {
  std::string id, scene, owner, obj, export_file, indicators, expert, rate_hz, count, csv, output;
  std::string speed, start_s, ticks, to_s;  // replays
  bool paused = false;
  std::vector<std::string> params;
};

// What a command runs with.
struct CommandCall {
  std::string command;
  std::string id;  // the session or class id after the command ("" none)
  CommandFlags flags;
  std::string token;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<hapsim::v1::SessionService::Stub> stub;
  grpc::ClientContext context;  // with the token and the --timeout-s deadline (`watch` streams with its own)
};

// What a command takes after its name: no id, one, or one optionally.
enum class IdArg { kNone, kOneId, kOptionalId };

struct Command {
  IdArg id;
  int (*run)(CommandCall& call);
  // The id is a session's: on a site of several servers, the call goes to
  // the server that hosts it (SessionService.Locate).
  bool follows_session = false;
};

// nullptr for an unknown name.
const Command* FindCommand(const std::string& name);
// Declares the command's own flags into *c.
void AddCommandFlags(const std::string& command, hapsim::common::Flags* f, CommandFlags* c);

// The trial-recording commands (ctl_recordings.cpp).
int RunRecordings(CommandCall& call);
int RunFetchRecording(CommandCall& call);
int RunDeleteRecording(CommandCall& call);
int RunReplay(CommandCall& call);
int RunReplayInfo(CommandCall& call);
int RunStep(CommandCall& call);
int RunSeek(CommandCall& call);

// "hapsim-ctl: MESSAGE (CODE)" on stderr; returns 1.
int ReportFailure(const grpc::Status& status);

// `watch` (ctl_watch.cpp): the class view as a table, until --count updates or Ctrl-C.
int Watch(CommandCall& call);

}  // namespace hapsim::ctl
