// The trial recordings' calls of the gRPC SessionService: list, fetch and
// delete (docs/recording.md). A recording is named by its path under the
// server's recordings directory ("SESSION/RUN-tNNNN.hrec") and looked up in
// the results database's index, never opened by a path a client made up.
// Visible as its session is (a trainee its own, instructors and observers
// their class's); deleting is an instructor's (create/close) right.
#pragma once
#include <optional>
#include <string>

#include "hapsim/classroom/access_policy.h"
#include "hapsim/store/results_store.h"
#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::service {

class RecordingCalls {
 public:
  // store: nullptr when the server keeps no data directory (the calls then
  // say so). policy: nullptr = development mode.
  RecordingCalls(ResultsStore* store, std::string recordings_dir, const AccessPolicy* policy);

  grpc::Status ListRecordings(grpc::ServerContext*, const hapsim::v1::RecordingQuery*, hapsim::v1::RecordingList*);
  // GetRecording over any writer (the gRPC stream's, or a test's).
  grpc::Status GetRecordingOn(grpc::ServerContext*, const hapsim::v1::RecordingRef*,
                              grpc::ServerWriterInterface<hapsim::v1::RecordingChunk>* writer);
  grpc::Status DeleteRecording(grpc::ServerContext*, const hapsim::v1::RecordingRef*,
                               hapsim::v1::DeleteRecordingResponse*);

  static constexpr std::size_t kChunkBytes = 256 * 1024;

  // The indexed recording named `id` (throws kNotFound; kFailedPrecondition
  // without a data directory), after checking the caller may do `action`
  // on its session.
  StoredRecording Find(const grpc::ServerContext* context, const std::string& id, Action action) const;
  std::string IdOf(const StoredRecording& r) const;

 private:
  void Describe(const StoredRecording& r, hapsim::v1::RecordingInfo* out) const;

  ResultsStore* store_;
  std::string recordings_dir_;  // with a trailing '/'
  const AccessPolicy* policy_;
};

}  // namespace hapsim::service
