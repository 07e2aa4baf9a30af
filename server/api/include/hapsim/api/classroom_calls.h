// The classroom's calls of the gRPC SessionService: the instructor's scores
// (SubmitScores, GetScores), the class view (WatchClass), pushing one
// scenario to a class (PushScenario) and the trial export (GetTrials). The
// wire keeps them in SessionService; here they are their own object, which
// SessionServiceImpl forwards to, so the session calls and the classroom
// calls each read as one concern. Every call first asks the AccessPolicy.
#pragma once
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/classroom/trial_book.h"
#include "hapsim/core/scenes/scene.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/viewer_hub.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class ClassroomCalls {
 public:
  // policy: nullptr = development mode. trials: nullptr = GetTrials refuses.
  ClassroomCalls(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores, const AccessPolicy* policy,
                 const TrialBook* trials);

  grpc::Status SubmitScores(grpc::ServerContext*, const hapsim::v1::SubmitScoresRequest*, hapsim::v1::ScoreReport*);
  grpc::Status GetScores(grpc::ServerContext*, const hapsim::v1::ScoreQuery*, hapsim::v1::ScoreReport*);
  // WatchClass over any writer: the gRPC stream's, or a test's or fuzzer's.
  grpc::Status WatchClassOn(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
                            grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer);
  grpc::Status PushScenario(grpc::ServerContext*, const hapsim::v1::PushScenarioRequest*,
                            hapsim::v1::PushScenarioResponse*);
  grpc::Status GetTrials(grpc::ServerContext*, const hapsim::v1::TrialQuery*, hapsim::v1::TrialReport*);
  // Ends every class view (OK status) and refuses new ones.
  void Stop();

  static constexpr double kDefaultWatchRateHz = 10.0;
  static constexpr double kMaxWatchRateHz = 50.0;
  static constexpr int kMaxWatchStreams = 16;  // each holds a server thread

 private:
  std::optional<Principal> Caller(const grpc::ServerContext* context) const;
  // The sessions of class `name` (nullptr: every session, development mode).
  const std::vector<std::string>* ClassSessions(const std::string& name, std::vector<std::string>* storage) const;
  // WatchClass's steps: take one of the kMaxWatchStreams places (or say why
  // not), then write the class's status at rate_hz until the instructor
  // leaves or the server stops (the caller gives the place back).
  grpc::Status AdmitWatchStream();
  void StreamClassStatus(grpc::ServerContext* context, const std::string& class_name,
                         const std::vector<std::string>* ids, double rate_hz,
                         grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer);
  // PushScenario to one session: closes it if open and creates it anew with
  // spec, for the same trainee; describes it in out.
  void RecreateSession(const std::string& id, const core::SceneSpec& spec, hapsim::v1::PushScenarioResponse* out);

  SessionRegistry* registry_;
  const ViewerHub* hub_;
  ScoreBook* scores_;
  const AccessPolicy* policy_;
  const TrialBook* trials_;
  std::mutex watch_mutex_;
  std::condition_variable watch_wake_;
  bool stopping_ = false;
  int watch_streams_ = 0;
};

}  // namespace hapsim::service
