// The class views of every console connection, shared: browsers that watch
// the same class with the same token and rate share one WatchClass stream
// of the server's (which allows 16 at once, each holding a server thread),
// and each status is encoded once for all of them. Thirty instructors'
// and observers' tabs on one class then cost one stream, not thirty.
// Every browser gets the newest status: one waiting per connection at most
// (ConsoleSession::OfferStatus), so a stalled tab holds nothing up.
#pragma once
#include <grpcpp/grpcpp.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "hapsim/v1/session.grpc.pb.h"

namespace hapsim::web {

class ConsoleSession;
class OpenCalls;

class ClassWatchHub {
 public:
  ClassWatchHub(std::shared_ptr<grpc::Channel> channel, OpenCalls* open_calls);
  ~ClassWatchHub();

  // `who` watches the class of `request` with `token` from now on (leaving
  // whatever it watched before): joins the stream of the same token, class
  // and rate, or starts one.
  void Join(const std::string& token, const hapsim::v1::WatchClassRequest& request,
            const std::shared_ptr<ConsoleSession>& who);
  // `who` watches nothing any more (its connection closed, or it left).
  void Leave(const ConsoleSession* who);

  class Watch;  // one shared WatchClass stream (its gRPC reactor)

 private:
  friend class Watch;
  void Deliver(Watch* watch, const hapsim::v1::ClassStatus& status);
  void Ended(Watch* watch, const grpc::Status& status);
  void LeaveLocked(const ConsoleSession* who, Watch** to_cancel);

  std::unique_ptr<hapsim::v1::SessionService::Stub> stub_;
  OpenCalls* open_calls_;
  // Recursive: cancelling a stream under it may end the stream inline, and
  // its end (Ended) takes it too. A stream found in the maps under it has
  // not been deleted.
  std::recursive_mutex mutex_;
  std::map<std::string, Watch*> by_key_;  // the live stream of each token, class and rate
  std::map<const ConsoleSession*, std::pair<Watch*, std::weak_ptr<ConsoleSession>>> members_;
};

}  // namespace hapsim::web
