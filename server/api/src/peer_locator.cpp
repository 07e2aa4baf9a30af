#include "hapsim/api/peer_locator.h"

#include <algorithm>
#include <condition_variable>
#include <mutex>

namespace hapsim::service {

PeerLocator::PeerLocator(ServerDirectory directory, std::string self_name,
                         std::shared_ptr<grpc::ChannelCredentials> credentials, std::chrono::milliseconds timeout)
    : directory_(std::move(directory)), self_name_(std::move(self_name)), timeout_(timeout) {
  for (const auto& server : directory_.servers) {
    if (server.name == self_name_) continue;
    peers_.push_back({&server, hapsim::v1::SessionService::NewStub(grpc::CreateChannel(server.address, credentials))});
  }
}

std::vector<PeerAnswer> PeerLocator::AskAll(const std::string& session_id, const std::string* authorization,
                                            std::chrono::system_clock::time_point deadline) const {
  deadline = std::min(deadline, std::chrono::system_clock::now() + timeout_);
  // One call per peer, all in flight at once; the callbacks count down.
  struct Call {
    grpc::ClientContext context;
    hapsim::v1::LocateRequest request;
  };
  std::vector<PeerAnswer> answers(peers_.size());
  std::vector<Call> calls(peers_.size());
  std::mutex mutex;
  std::condition_variable all_done;
  std::size_t pending = peers_.size();
  for (std::size_t i = 0; i < peers_.size(); ++i) {
    answers[i].server = peers_[i].server;
    calls[i].context.set_deadline(deadline);
    if (authorization) calls[i].context.AddMetadata("authorization", *authorization);
    calls[i].request.set_session_id(session_id);
    calls[i].request.set_local_only(true);  // peers never ask further: no loops
    peers_[i].stub->async()->Locate(&calls[i].context, &calls[i].request, &answers[i].response,
                                    [&, i](grpc::Status status) {
                                      std::lock_guard lock(mutex);
                                      answers[i].status = std::move(status);
                                      if (--pending == 0) all_done.notify_one();
                                    });
  }
  // Every call ends by its deadline (gRPC cancels it then), so this wait is bounded.
  std::unique_lock lock(mutex);
  all_done.wait(lock, [&] { return pending == 0; });
  return answers;
}

}  // namespace hapsim::service
