// hapsim-load's use of the SessionService: create the sessions its devices
// drive, read the server's counters of each after the run, close them.
// Kept out of hapsim::bridge so the bridge library never links gRPC.
#pragma once
#include <string>
#include <vector>

#include "hapsim/load/load_plan.h"
#include "hapsim/load/load_report.h"
#include "hapsim/viewer/session_client.h"

namespace hapsim::bridge {

struct SessionSpec {
  std::string scene;
  std::string params;  // "k=v,k=v" (scene parameters, SI)
  std::string owner = "hapsim-load";
};

// "" if every KEY=NUMBER in the comma list parses, else what is wrong (the
// caller exits 2 before starting anything).
std::string CheckSceneParams(const std::string& params);

// Creates one session per planned device, in order. On the first failure it
// closes the ones it created and returns the error ("session 'x': CODE:
// server message"); on success returns "" and *created lists every id.
std::string CreateSessions(viewer::SessionClient& client, const std::vector<LoadDevicePlan>& plan,
                           const SessionSpec& spec, std::vector<std::string>* created);
// Closes each; returns one line per failure ("" when all closed).
std::string CloseSessions(viewer::SessionClient& client, const std::vector<std::string>& ids);
std::vector<ServerSessionStats> FetchServerStats(viewer::SessionClient& client, const std::vector<LoadDevicePlan>& plan);

}  // namespace hapsim::bridge
