// gRPC SessionService: sessions (create/list/get/close/pause/resume/reset),
// scene catalogue, mesh snapshots and device binding (JoinSession). Its
// classroom calls (scores, WatchClass, PushScenario, GetTrials) are
// answered by ClassroomCalls. Synchronous API: every call but WatchClass is
// short, and none touches a session's tick directly. Every call first asks
// the AccessPolicy who the caller is and whether it may (docs/classroom.md).
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "hapsim/api/classroom_calls.h"
#include "hapsim/api/locate_call.h"
#include "hapsim/api/recording_calls.h"
#include "hapsim/api/replay_calls.h"
#include "hapsim/classroom/access_policy.h"
#include "hapsim/classroom/score_book.h"
#include "hapsim/classroom/trial_book.h"
#include "hapsim/runtime/session_registry.h"
#include "hapsim/streaming/viewer_hub.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class SessionServiceImpl final : public hapsim::v1::SessionService::Service {
 public:
  // policy: nullptr = development mode (no tokens). dds_domain: what
  // JoinSession tells devices. peers: the site's other servers (nullptr:
  // no directory; Locate answers for this server's sessions only).
  SessionServiceImpl(SessionRegistry* registry, const ViewerHub* hub, ScoreBook* scores,
                     const AccessPolicy* policy = nullptr, std::uint32_t dds_domain = 0,
                     const TrialBook* trials = nullptr, ResultsStore* store = nullptr, std::string recordings_dir = {},
                     const PeerLocator* peers = nullptr);

  // Ends every WatchClass stream (OK status) and refuses new ones; called
  // before the gRPC server shuts down so no handler thread outlives it.
  void Stop() { classroom_.Stop(); }

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
  grpc::Status SubmitScores(grpc::ServerContext* c, const hapsim::v1::SubmitScoresRequest* req,
                            hapsim::v1::ScoreReport* out) override {
    return classroom_.SubmitScores(c, req, out);
  }
  grpc::Status GetScores(grpc::ServerContext* c, const hapsim::v1::ScoreQuery* req,
                         hapsim::v1::ScoreReport* out) override {
    return classroom_.GetScores(c, req, out);
  }
  grpc::Status JoinSession(grpc::ServerContext*, const hapsim::v1::SessionRef*,
                           hapsim::v1::JoinSessionResponse*) override;
  grpc::Status WatchClass(grpc::ServerContext* c, const hapsim::v1::WatchClassRequest* req,
                          grpc::ServerWriter<hapsim::v1::ClassStatus>* writer) override {
    return classroom_.WatchClassOn(c, req, writer);
  }
  // WatchClass over any writer: the gRPC stream's, or a test's or fuzzer's
  // (grpc::ServerWriter cannot be made outside a call).
  grpc::Status WatchClassOn(grpc::ServerContext* context, const hapsim::v1::WatchClassRequest* req,
                            grpc::ServerWriterInterface<hapsim::v1::ClassStatus>* writer) {
    return classroom_.WatchClassOn(context, req, writer);
  }
  grpc::Status PushScenario(grpc::ServerContext* c, const hapsim::v1::PushScenarioRequest* req,
                            hapsim::v1::PushScenarioResponse* out) override {
    return classroom_.PushScenario(c, req, out);
  }
  grpc::Status GetTrials(grpc::ServerContext* c, const hapsim::v1::TrialQuery* req,
                         hapsim::v1::TrialReport* out) override {
    return classroom_.GetTrials(c, req, out);
  }
  grpc::Status ListRecordings(grpc::ServerContext* c, const hapsim::v1::RecordingQuery* req,
                              hapsim::v1::RecordingList* out) override {
    return recordings_.ListRecordings(c, req, out);
  }
  grpc::Status GetRecording(grpc::ServerContext* c, const hapsim::v1::RecordingRef* req,
                            grpc::ServerWriter<hapsim::v1::RecordingChunk>* writer) override {
    return recordings_.GetRecordingOn(c, req, writer);
  }
  grpc::Status DeleteRecording(grpc::ServerContext* c, const hapsim::v1::RecordingRef* req,
                               hapsim::v1::DeleteRecordingResponse* out) override {
    return recordings_.DeleteRecording(c, req, out);
  }
  grpc::Status OpenReplay(grpc::ServerContext* c, const hapsim::v1::OpenReplayRequest* req,
                          hapsim::v1::ReplayInfo* out) override {
    return replays_.OpenReplay(c, req, out);
  }
  grpc::Status GetReplay(grpc::ServerContext* c, const hapsim::v1::SessionRef* req,
                         hapsim::v1::ReplayInfo* out) override {
    return replays_.GetReplay(c, req, out);
  }
  grpc::Status StepReplay(grpc::ServerContext* c, const hapsim::v1::StepReplayRequest* req,
                          hapsim::v1::ReplayInfo* out) override {
    return replays_.StepReplay(c, req, out);
  }
  grpc::Status SeekReplay(grpc::ServerContext* c, const hapsim::v1::SeekReplayRequest* req,
                          hapsim::v1::ReplayInfo* out) override {
    return replays_.SeekReplay(c, req, out);
  }
  grpc::Status Locate(grpc::ServerContext* c, const hapsim::v1::LocateRequest* req,
                      hapsim::v1::LocateResponse* out) override {
    return locate_.Locate(c, req, out);
  }

  static constexpr int kMaxWatchStreams = ClassroomCalls::kMaxWatchStreams;

 private:
  std::optional<Principal> Caller(const grpc::ServerContext* context) const;
  std::shared_ptr<const SceneSnapshot> SnapshotWithMesh(Session& session, grpc::ServerContext& context) const;
  SessionRegistry* registry_;
  const ViewerHub* hub_;
  const AccessPolicy* policy_;
  std::uint32_t dds_domain_;
  ClassroomCalls classroom_;
  RecordingCalls recordings_;
  ReplayCalls replays_;  // after recordings_, which it uses
  LocateCall locate_;
};

// Fills a SessionInfo from a session's counters.
void DescribeSession(const Session& session, hapsim::v1::SessionInfo* info);

}  // namespace hapsim::service
