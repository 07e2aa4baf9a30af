#include "hapsim/dds/io_thread.h"

#include <array>

#include "hapsim/common/thread_setup.h"

namespace hapsim::dds {

IoThread::IoThread(const Participant& participant, std::int64_t wake_timeout_ns, Scheduling scheduling)
    : waitset_(participant), wake_timeout_ns_(wake_timeout_ns), scheduling_(scheduling) {}

IoThread::~IoThread() { Stop(); }

void IoThread::Start(Handlers handlers) {
  Stop();
  handlers_ = std::move(handlers);
  stop_ = false;
  thread_ = std::thread([this] { Run(); });
  common::NameThread(thread_, kThreadName);  // found by name for real-time priority
  if (scheduling_ == Scheduling::kBatch) common::RunThreadInBatch(thread_);
}

void IoThread::Stop() {
  stop_ = true;
  waitset_.Wake();
  if (thread_.joinable()) thread_.join();
}

void IoThread::Run() {
  // More triggered readers than this are reported on the next pass (their
  // conditions stay triggered while they hold samples).
  std::array<dds_attach_t, 64> tags;
  while (!stop_.load()) {
    const std::size_t n = waitset_.Wait(wake_timeout_ns_, tags);
    if (handlers_.on_wake) handlers_.on_wake();
    for (std::size_t i = 0; i < n; ++i) {
      if (tags[i] != WaitSet::kGuardTag && handlers_.on_reader) handlers_.on_reader(tags[i]);
    }
  }
}

bool IsDdsThread(const std::string& name) {
  // Cyclone's own threads (receive, delivery queues, timed events, garbage
  // collection) and ours.
  for (const char* dds_name :
       {"recv", "recvUC", "recvMC", "dq.user", "dq.builtins", "tev", "gc", IoThread::kThreadName}) {
    if (name == dds_name) return true;
  }
  return false;
}

common::RealtimeResult RaiseDdsThreads(int priority) { return common::RaiseThreadsWhere(IsDdsThread, priority); }

}  // namespace hapsim::dds
