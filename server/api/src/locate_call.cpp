#include "hapsim/api/locate_call.h"

#include <spdlog/spdlog.h>

#include "hapsim/api/call_status.h"
#include "hapsim/common/session_id.h"

namespace hapsim::service {

namespace {

std::string Describe(const DirectoryEntry& server) { return server.name + " (" + server.address + ")"; }

}  // namespace

LocateCall::LocateCall(const SessionRegistry* registry, const AccessPolicy* policy, const PeerLocator* peers)
    : registry_(registry), policy_(policy), peers_(peers) {}

grpc::Status LocateCall::Locate(grpc::ServerContext* context, const hapsim::v1::LocateRequest* request,
                                hapsim::v1::LocateResponse* out) const {
  return Guarded("Locate", [&] {
    const std::string& id = request->session_id();
    if (!common::IsValidSessionId(id)) {
      throw ServiceError(ErrorCode::kInvalidArgument, "session id must be 1-63 of [A-Za-z0-9_-]");
    }
    out->set_session_id(id);
    if (registry_->Find(id)) return AnswerHere(context, id, out);
    if (request->local_only() || !peers_) {
      throw ServiceError(ErrorCode::kNotFound, "no session '" + id + "' on this server" +
                                                   (peers_ ? "" : " (it has no --directory of other servers)"));
    }
    AnswerFromPeers(context, id, out);
  });
}

void LocateCall::AnswerHere(const grpc::ServerContext* context, const std::string& id,
                            hapsim::v1::LocateResponse* out) const {
  policy_->Authorize(AuthenticateCall(*policy_, context), Action::kView, id);
  out->set_on_this_server(true);
  if (peers_) {
    out->set_server_name(peers_->self_name());
    if (const auto* self = peers_->self()) out->set_address(self->address);
  }
  if (const auto* cls = policy_->ClassOf(id)) out->set_class_name(cls->name);
}

void LocateCall::AnswerFromPeers(const grpc::ServerContext* context, const std::string& id,
                                 hapsim::v1::LocateResponse* out) const {
  const auto authorization = AuthorizationOf(context);
  const auto answers = peers_->AskAll(id, authorization ? &*authorization : nullptr, context->deadline());
  const PeerAnswer* host = nullptr;
  const PeerAnswer* refused = nullptr;
  for (const auto& a : answers) {
    const auto code = a.status.error_code();
    if (code == grpc::StatusCode::OK) {
      if (!host) {
        host = &a;
      } else {
        out->add_also_on(Describe(*a.server));
      }
    } else if (code == grpc::StatusCode::UNAUTHENTICATED || code == grpc::StatusCode::PERMISSION_DENIED) {
      if (!refused) refused = &a;  // it hosts the session, but not for this caller
    } else if (code != grpc::StatusCode::NOT_FOUND) {
      out->add_unreachable(Describe(*a.server) + ": " + a.status.error_message());
    }
  }
  if (host) {
    out->set_server_name(host->server->name);
    out->set_address(host->server->address);
    out->set_class_name(host->response.class_name());
    if (out->also_on_size() > 0) {
      spdlog::warn("session '{}' is on more than one server: {} and {} (session ids must be unique on a site)", id,
                   host->server->name, out->also_on(0));
    }
    return;
  }
  if (refused) {
    throw ServiceError(refused->status.error_code() == grpc::StatusCode::UNAUTHENTICATED ? ErrorCode::kUnauthenticated
                                                                                         : ErrorCode::kPermissionDenied,
                       "server " + refused->server->name + " refused: " + refused->status.error_message());
  }
  if (out->unreachable_size() > 0) {
    std::string which;
    for (const auto& u : out->unreachable()) which += (which.empty() ? "" : "; ") + u;
    throw ServiceError(ErrorCode::kUnavailable,
                       "session '" + id + "' is on no server that answered; these did not: " + which);
  }
  throw ServiceError(ErrorCode::kNotFound, "no session '" + id + "' on any of the " +
                                               std::to_string(peers_->directory().servers.size()) +
                                               " servers of the directory");
}

}  // namespace hapsim::service
