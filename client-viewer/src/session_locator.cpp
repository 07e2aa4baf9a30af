#include "hapsim/viewer/session_locator.h"

#include <chrono>

#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::viewer {

SessionLocation LocateSession(const Connection& asked, const std::string& session_id, double timeout_s,
                              bool wait_for_server) {
  SessionLocation location;
  location.connection = asked;
  const auto channel = MakeChannel(asked);
  auto stub = hapsim::v1::SessionService::NewStub(channel);
  grpc::ClientContext context;
  AddToken(&context, asked.token);
  context.set_wait_for_ready(wait_for_server);
  context.set_deadline(
      std::chrono::system_clock::now() +
      std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(timeout_s)));
  hapsim::v1::LocateRequest request;
  request.set_session_id(session_id);
  location.status = stub->Locate(&context, request, &location.where);
  // A status the server sent comes over a connected channel; a transport
  // failure or a timeout waiting for the server leaves it unconnected.
  location.answered = location.status.ok() || channel->GetState(false) == GRPC_CHANNEL_READY;
  if (location.status.ok() && !location.where.on_this_server() && !location.where.address().empty()) {
    location.connection.address = location.where.address();
    location.moved = true;
  }
  return location;
}

bool LocateStopsTheClient(const SessionLocation& location) {
  if (!location.answered) return false;
  const auto code = location.status.error_code();
  return code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::UNAUTHENTICATED ||
         code == grpc::StatusCode::PERMISSION_DENIED;
}

std::string DescribeLocation(const SessionLocation& l) {
  std::string text = "session " + l.where.session_id() + " is on ";
  text += l.where.server_name().empty() ? std::string("the asked server") : l.where.server_name();
  if (!l.where.address().empty()) text += " (" + l.where.address() + ")";
  return text;
}

}  // namespace hapsim::viewer
