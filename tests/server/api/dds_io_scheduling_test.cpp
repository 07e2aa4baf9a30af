// The DDS thread that routes poses runs in SCHED_BATCH unless asked
// otherwise: woken by Cyclone's receive thread, it waits for it to finish
// instead of preempting it (ServerOptions::dds_io_scheduling).
#include <gtest/gtest.h>
#include <sched.h>

#include <string>
#include <vector>

#include "hapsim/app/server_app.h"
#include "hapsim/dds/io_thread.h"
#include "hapsim/runtime/tick_pool.h"
#include "test_dds_domain.h"
#include "threads_of_this_process.h"

namespace hapsim::service {
namespace {

// The scheduling policy (SCHED_OTHER, SCHED_BATCH, ...) of every thread of
// this process with that name.
std::vector<int> PoliciesOfThreadsNamed(const std::string& wanted) {
  std::vector<int> policies;
  for (const auto& t : test::ThreadsOfThisProcess())
    if (t.name == wanted) policies.push_back(sched_getscheduler(t.tid));
  return policies;
}

std::vector<int> PoliciesUnder(dds::IoThread::Scheduling scheduling, const std::string& thread_name) {
  ServerOptions o;
  o.listen_address = "127.0.0.1:0";
  o.dds.domain_id = test::ClaimTestDdsDomain();
  o.workers = 1;
  o.dds_io_scheduling = scheduling;
  ServerApp app(o);
  std::vector<int> policies = PoliciesOfThreadsNamed(thread_name);
  app.Shutdown();
  return policies;
}

TEST(DdsIoSchedulingTest, TheRoutingThreadRunsInBatchByDefaultAndTheTickWorkersStayNormal) {
  EXPECT_EQ(ServerOptions{}.dds_io_scheduling, dds::IoThread::Scheduling::kBatch);
  EXPECT_EQ(PoliciesUnder(dds::IoThread::Scheduling::kBatch, dds::IoThread::kThreadName),
            std::vector<int>{SCHED_BATCH});
  // The ticks it wakes keep preempting it: a due tick must not wait for a slice.
  EXPECT_EQ(PoliciesUnder(dds::IoThread::Scheduling::kBatch, TickPool::kWorkerThreadName),
            std::vector<int>{SCHED_OTHER});
}

TEST(DdsIoSchedulingTest, NormalSchedulingIsKeptWhenAskedFor) {
  EXPECT_EQ(PoliciesUnder(dds::IoThread::Scheduling::kNormal, dds::IoThread::kThreadName),
            std::vector<int>{SCHED_OTHER});
}

}  // namespace
}  // namespace hapsim::service
