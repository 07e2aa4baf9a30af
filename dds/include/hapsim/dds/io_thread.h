// The DDS I/O thread every process runs: it sleeps on a waitset and, on
// each wake (a reader has data, Wake() was called, or the timeout passed),
// runs on_wake() and then on_reader(tag) once per triggered reader, with the
// tag the reader was attached with. The server attaches one pose reader per
// session (tag: the session), a bridge or the load generator one force-model
// reader per device (tag: its slot + 1). Real-time threads never wait on it:
// they post into mailboxes and call Wake() (cheap, thread-safe).
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include "hapsim/common/thread_setup.h"
#include "hapsim/dds/dds.h"

namespace hapsim::dds {

class IoThread {
 public:
  struct Handlers {
    std::function<void()> on_wake;                 // every wake, before the readers (may be empty)
    std::function<void(dds_attach_t)> on_reader;   // a triggered reader's tag
  };

  // How the thread is scheduled. kNormal: a sample's arrival preempts
  // whatever runs on the core (the thread is woken by Cyclone's receive
  // thread). kBatch: it waits until the receive thread blocks (common::
  // RunThreadInBatch) and then takes every sample that arrived meanwhile
  // in one wake — on a busy server, a fraction of the context switches
  // (docs/performance.md, "The DDS thread waits its turn").
  enum class Scheduling { kNormal, kBatch };

  // wake_timeout_ns: the thread wakes at least this often.
  static constexpr std::int64_t kDefaultWakeTimeoutNs = 5'000'000;
  explicit IoThread(const Participant& participant, std::int64_t wake_timeout_ns = kDefaultWakeTimeoutNs,
                    Scheduling scheduling = Scheduling::kNormal);
  static constexpr const char* kThreadName = "dds-io";
  ~IoThread();
  IoThread(const IoThread&) = delete;
  IoThread& operator=(const IoThread&) = delete;

  // A reader's samples wake the thread and are reported with `tag` (any
  // value but WaitSet::kGuardTag) until the returned condition is
  // destroyed. Thread-safe against a running thread.
  Entity AttachReader(dds_entity_t reader, dds_attach_t tag) { return waitset_.AttachReader(reader, tag); }

  void Start(Handlers handlers);
  void Stop();  // joins; idempotent
  void Wake() { waitset_.Wake(); }

 private:
  void Run();

  WaitSet waitset_;
  std::int64_t wake_timeout_ns_;
  Scheduling scheduling_;
  Handlers handlers_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// Real-time priority (common::RaiseThreadsNamed) for every DDS thread of
// the process: Cyclone's own (receive "recv"/"recvUC"/"recvMC", delivery
// queues "dq.*", timed events "tev" — heartbeats and acks —, "gc") and this
// process's IoThread. All of them, not only the receive path: a real-time
// thread writing a sample takes locks Cyclone's other threads hold too, and
// one of those left at normal priority behind busy programs on the core
// stalls the writer (priority inversion: measured, a 1 kHz bridge's round
// trip grew to seconds). They do little work each. Call after the
// participant exists and the IoThread started.
common::RealtimeResult RaiseDdsThreads(int priority);
// Whether a thread of this name is one of those.
bool IsDdsThread(const std::string& name);

}  // namespace hapsim::dds
