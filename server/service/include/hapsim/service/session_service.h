// gRPC SessionService: sessions (create/list/get/close/pause/resume/reset),
// scene catalogue, mesh snapshots and the instructor's scoring. Synchronous
// API: every call is short and never touches a session's tick directly.
#pragma once
#include "hapsim/service/score_book.h"
#include "hapsim/service/session_registry.h"
#include "hapsim/service/viewer_hub.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class SessionServiceImpl final : public hapsim::v1::SessionService::Service {
 public:
  SessionServiceImpl(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores)
      : registry_(registry), hub_(hub), scores_(scores) {}

  grpc::Status ListScenes(grpc::ServerContext*, const hapsim::v1::ListScenesRequest*,
                          hapsim::v1::ListScenesResponse*) override;
  grpc::Status CreateSession(grpc::ServerContext*, const hapsim::v1::CreateSessionRequest*,
                             hapsim::v1::SessionInfo*) override;
  grpc::Status ListSessions(grpc::ServerContext*, const hapsim::v1::ListSessionsRequest*,
                            hapsim::v1::ListSessionsResponse*) override;
  grpc::Status GetSession(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::SessionInfo*) override;
  grpc::Status CloseSession(grpc::ServerContext*, const hapsim::v1::SessionRef*,
                            hapsim::v1::CloseSessionResponse*) override;
  grpc::Status PauseSession(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::SessionInfo*) override;
  grpc::Status ResumeSession(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::SessionInfo*) override;
  grpc::Status ResetSession(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::SessionInfo*) override;
  grpc::Status GetSnapshot(grpc::ServerContext*, const hapsim::v1::SessionRef*, hapsim::v1::MeshSnapshot*) override;
  grpc::Status SubmitScores(grpc::ServerContext*, const hapsim::v1::SubmitScoresRequest*,
                            hapsim::v1::ScoreReport*) override;
  grpc::Status GetScores(grpc::ServerContext*, const hapsim::v1::ScoreQuery*, hapsim::v1::ScoreReport*) override;

 private:
  SessionRegistry* registry_;
  const ViewerHub* hub_;
  ScoreBook* scores_;
};

// Fills a SessionInfo from a session's counters.
void DescribeSession(const Session& session, hapsim::v1::SessionInfo* info);
grpc::Status ToGrpcStatus(const ServiceError& e);

}  // namespace hapsim::service
