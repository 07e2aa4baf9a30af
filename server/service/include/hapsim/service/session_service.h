// gRPC SessionService: sessions (create/list/get/close/pause/resume/reset),
// scene catalogue, mesh snapshots, the instructor's scoring, device binding
// (JoinSession), the class view (WatchClass) and pushing one scenario to a
// class. Synchronous API: every call but WatchClass is short, and none
// touches a session's tick directly. Every call first asks the AccessPolicy
// who the caller is and whether it may (docs/classroom.md).
#pragma once
#include <condition_variable>
#include <mutex>

#include "hapsim/service/access_policy.h"
#include "hapsim/service/score_book.h"
#include "hapsim/service/trial_book.h"
#include "hapsim/service/session_registry.h"
#include "hapsim/service/viewer_hub.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class SessionServiceImpl final : public hapsim::v1::SessionService::Service {
 public:
  // policy: nullptr = development mode (no tokens). dds_domain: what
  // JoinSession tells devices.
  SessionServiceImpl(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores,
                     const AccessPolicy* policy = nullptr, std::uint32_t dds_domain = 0,
                     const TrialBook* trials = nullptr);

  // Ends every WatchClass stream (OK status) and refuses new ones; called
  // before the gRPC server shuts down so no handler thread outlives it.
  void Stop();

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
  grpc::Status JoinSession(grpc::ServerContext*, const hapsim::v1::SessionRef*,
                           hapsim::v1::JoinSessionResponse*) override;
  grpc::Status WatchClass(grpc::ServerContext*, const hapsim::v1::WatchClassRequest*,
                          grpc::ServerWriter<hapsim::v1::ClassStatus>*) override;
  // WatchClass over any writer: the gRPC stream's, or a test's or fuzzer's
  // (grpc::ServerWriter cannot be made outside a call).
  grpc::Status WatchClassOn(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
                            grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer);
  grpc::Status PushScenario(grpc::ServerContext*, const hapsim::v1::PushScenarioRequest*,
                            hapsim::v1::PushScenarioResponse*) override;
  grpc::Status GetTrials(grpc::ServerContext*, const hapsim::v1::TrialQuery*, hapsim::v1::TrialReport*) override;

  static constexpr double kDefaultWatchRateHz = 10.0;
  static constexpr double kMaxWatchRateHz = 50.0;
  static constexpr int kMaxWatchStreams = 16;  // each holds a server thread

 private:
  std::optional<Principal> Caller(const grpc::ServerContext* context) const;
  // What the class config says of a session (trainee, trial targets); empty
  // for a session in no class.
  struct Placement {
    std::string trainee;
    TrialTargets targets;
  };
  Placement PlacementOf(const std::string& session_id) const;
  // The sessions of class `name` (nullptr: every session, development mode).
  const std::vector<std::string>* ClassSessions(const std::string& name, std::vector<std::string>* storage) const;

  SessionRegistry* registry_;
  const ViewerHub* hub_;
  ScoreBook* scores_;
  const AccessPolicy* policy_;
  std::uint32_t dds_domain_;
  const TrialBook* trials_;
  std::mutex watch_mutex_;
  std::condition_variable watch_wake_;
  bool stopping_ = false;
  int watch_streams_ = 0;
};

// The caller behind a gRPC call's metadata ("authorization"), for every
// service: nullopt in development mode; throws ServiceError(kUnauthenticated).
std::optional<Principal> AuthenticateCall(const AccessPolicy& policy, const grpc::ServerContextBase* context);

// Fills a SessionInfo from a session's counters.
void DescribeSession(const Session& session, hapsim::v1::SessionInfo* info);
grpc::Status ToGrpcStatus(const ServiceError& e);

}  // namespace hapsim::service
