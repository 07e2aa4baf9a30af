#include "hapsim/api/recording_calls.h"

#include <filesystem>
#include <fstream>

#include "hapsim/api/call_status.h"

namespace hapsim::service {

RecordingCalls::RecordingCalls(ResultsStore* store, std::string recordings_dir, const AccessPolicy* policy)
    : store_(store), recordings_dir_(std::move(recordings_dir)), policy_(policy ? policy : &OpenAccessPolicy()) {
  if (!recordings_dir_.empty() && recordings_dir_.back() != '/') recordings_dir_ += '/';
}

std::string RecordingCalls::IdOf(const StoredRecording& r) const {
  return r.path.rfind(recordings_dir_, 0) == 0 ? r.path.substr(recordings_dir_.size()) : r.path;
}

void RecordingCalls::Describe(const StoredRecording& r, hapsim::v1::RecordingInfo* out) const {
  out->set_id(IdOf(r));
  out->set_session_id(r.session_id);
  out->set_run_id(r.run_id);
  out->set_trial(r.trial);
  out->set_trainee(r.trainee);
  out->set_class_name(r.class_name);
  out->set_scene(r.scene);
  out->set_started_unix_ms(r.started_unix_ms);
  out->set_ended_unix_ms(r.ended_unix_ms.value_or(0));
  out->set_ticks(r.ticks);
  out->set_bytes(r.bytes);
  out->set_status(r.status);
}

StoredRecording RecordingCalls::Find(const grpc::ServerContext* context, const std::string& id, Action action) const {
  const auto who = AuthenticateCall(*policy_, context);
  if (!store_) throw ServiceError(ErrorCode::kFailedPrecondition, "this server keeps no recordings (no --data-dir)");
  if (id.empty() || id.size() > 256) throw ServiceError(ErrorCode::kInvalidArgument, "give a recording id");
  for (const auto& r : store_->Recordings()) {
    if (r.status == "deleted" || IdOf(r) != id) continue;
    policy_->Authorize(who, action, r.session_id);
    return r;
  }
  throw ServiceError(ErrorCode::kNotFound, "no recording '" + id.substr(0, 120) + "'");
}

grpc::Status RecordingCalls::ListRecordings(grpc::ServerContext* context, const hapsim::v1::RecordingQuery* req,
                                            hapsim::v1::RecordingList* out) {
  return Guarded("ListRecordings", [&] {
    const auto who = AuthenticateCall(*policy_, context);
    if (!req->session_id().empty()) policy_->Authorize(who, Action::kView, req->session_id());
    if (!store_) throw ServiceError(ErrorCode::kFailedPrecondition, "this server keeps no recordings (no --data-dir)");
    for (const auto& r : store_->Recordings()) {
      if (r.status == "deleted") continue;
      if (!req->session_id().empty() && r.session_id != req->session_id()) continue;
      if (!policy_->Allows(who, Action::kView, r.session_id)) continue;
      Describe(r, out->add_recordings());
    }
  });
}

grpc::Status RecordingCalls::GetRecordingOn(grpc::ServerContext* context, const hapsim::v1::RecordingRef* req,
                                            grpc::ServerWriterInterface<hapsim::v1::RecordingChunk>* writer) {
  return Guarded("GetRecording", [&] {
    const StoredRecording r = Find(context, req->id(), Action::kView);
    std::ifstream in(r.path, std::ios::binary);
    if (!in) throw ServiceError(ErrorCode::kNotFound, "recording '" + req->id() + "' is indexed but its file is gone");
    // A running trial's file is read up to where it is now; its last record
    // may be half written, which the reader reports as a torn end.
    std::string buffer(kChunkBytes, '\0');
    std::uint64_t offset = 0;
    while (true) {
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      const auto got = static_cast<std::size_t>(in.gcount());
      hapsim::v1::RecordingChunk chunk;
      chunk.set_data(buffer.data(), got);
      chunk.set_offset(offset);
      chunk.set_last(got < buffer.size());
      offset += got;
      if (!writer->Write(chunk)) return;  // the client went away
      if (chunk.last() || context->IsCancelled()) return;
    }
  });
}

grpc::Status RecordingCalls::DeleteRecording(grpc::ServerContext* context, const hapsim::v1::RecordingRef* req,
                                             hapsim::v1::DeleteRecordingResponse*) {
  return Guarded("DeleteRecording", [&] {
    const StoredRecording r = Find(context, req->id(), Action::kCreateClose);
    if (r.status == "open") {
      throw ServiceError(ErrorCode::kFailedPrecondition,
                         "recording '" + req->id() + "' is of a running trial: reset or close the session first");
    }
    std::error_code error;
    std::filesystem::remove(r.path, error);
    if (error) throw std::runtime_error("cannot delete " + req->id() + ": " + error.message());
    store_->MarkRecordingDeleted(r.path);
    store_->Flush();  // deleted means gone from the list the caller reads next
  });
}

}  // namespace hapsim::service
