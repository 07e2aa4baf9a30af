// SessionService.Locate: where a session runs on a site of several servers
// (docs/deploy.md, "Several servers"). This server's own sessions are
// answered here (to whoever may view them); any other id is asked of every
// other server of the directory, which answer for their own. No server
// keeps a map of the others' sessions, so a restarted or moved server is
// found as soon as it answers.
#pragma once
#include <grpcpp/grpcpp.h>

#include "hapsim/api/peer_locator.h"
#include "hapsim/classroom/access_policy.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class LocateCall {
 public:
  // peers: nullptr when the server has no directory (it then answers for
  // its own sessions only). policy: never nullptr.
  LocateCall(const SessionRegistry* registry, const AccessPolicy* policy, const PeerLocator* peers);

  grpc::Status Locate(grpc::ServerContext* context, const hapsim::v1::LocateRequest* request,
                      hapsim::v1::LocateResponse* out) const;

 private:
  // This server's own session, to a caller who may view it.
  void AnswerHere(const grpc::ServerContext* context, const std::string& session_id,
                  hapsim::v1::LocateResponse* out) const;
  // Throws kNotFound / kUnavailable / the hosting server's refusal.
  void AnswerFromPeers(const grpc::ServerContext* context, const std::string& session_id,
                       hapsim::v1::LocateResponse* out) const;

  const SessionRegistry* registry_;
  const AccessPolicy* policy_;
  const PeerLocator* peers_;
};

}  // namespace hapsim::service
