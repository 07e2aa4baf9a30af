// Where a session runs, for clients of a site with several servers: the
// server the user named is asked (SessionService.Locate); if another server
// of its directory hosts the session, the client talks to that one. Used by
// hapsim-ctl, hapsim-viewer and hapsim-bridge --locate-via.
#pragma once
#include <grpcpp/grpcpp.h>

#include <string>

#include "hapsim/v1/session.pb.h"
#include "hapsim/viewer/connection.h"

namespace hapsim::viewer {

struct SessionLocation {
  grpc::Status status;  // Locate's answer
  hapsim::v1::LocateResponse where;
  Connection connection;  // the server to use: the asked one, or the one hosting the session
  bool moved = false;     // connection points at another server than the asked one
  bool answered = false;  // the asked server answered (not a transport failure or a timeout)
};

// Asks `asked` where `session_id` runs, within timeout_s; with
// wait_for_server, a server not up yet is waited for that long (a viewer
// may start before its server), else it fails at once (UNAVAILABLE). TLS
// and token stay the asked connection's: one site, one CA.
SessionLocation LocateSession(const Connection& asked, const std::string& session_id, double timeout_s,
                              bool wait_for_server);

// Whether a client stops on a Locate answer instead of going on with the
// asked server: that server answered that the session's server did not
// answer (UNAVAILABLE) or refused the caller. NOT_FOUND, an older server
// without Locate (UNIMPLEMENTED), or no answer from the asked server at all
// let the client's own call (and its own checks) say what is wrong.
bool LocateStopsTheClient(const SessionLocation& location);

// "session S is on NAME (ADDRESS)", for a client's log.
std::string DescribeLocation(const SessionLocation& location);

}  // namespace hapsim::viewer
