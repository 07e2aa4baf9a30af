// --tick-cpus: the 1 kHz path on its own CPUs, everything else off them —
// the threads there at start and those started later by a call alike.
#include <gtest/gtest.h>
#include <sys/types.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "hapsim/app/server_app.h"
#include "hapsim/common/thread_setup.h"
#include "hapsim/dds/io_thread.h"
#include "hapsim/runtime/tick_pool.h"
#include "hapsim/v1/session.grpc.pb.h"
#include "test_dds_domain.h"
#include "threads_of_this_process.h"

namespace hapsim::service {
namespace {

struct ThreadCpus {
  std::string name;
  std::vector<int> cpus;
};

std::vector<ThreadCpus> CpusOfEachThread() {
  std::vector<ThreadCpus> threads;
  for (const auto& t : test::ThreadsOfThisProcess()) threads.push_back({t.name, common::CpusOfThread(t.tid)});
  return threads;
}

bool OnTickPath(const std::string& name) { return name == TickPool::kWorkerThreadName || dds::IsDdsThread(name); }

TEST(TickCpusTest, TheTickPathRunsOnlyOnItsCpusAndEveryOtherThreadOnlyElsewhere) {
  const std::vector<int> mine = common::CpusOfThread(0);
  if (mine.size() < 2) GTEST_SKIP() << "needs two CPUs (this process may use " << mine.size() << ")";
  const int tick_cpu = mine.back();
  std::vector<int> rest(mine.begin(), mine.end() - 1);

  ServerOptions o;
  o.listen_address = "127.0.0.1:0";
  o.dds.domain_id = test::ClaimTestDdsDomain();
  o.tick_cpus = {tick_cpu};
  ServerApp app(o);
  EXPECT_EQ(app.pool().workers(), 1) << "one worker per tick CPU by default";
  // A call and a session after the split: gRPC and the session start threads of their own.
  auto channel =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(app.bound_port()), grpc::InsecureChannelCredentials());
  auto sessions = hapsim::v1::SessionService::NewStub(channel);
  grpc::ClientContext ctx;
  hapsim::v1::CreateSessionRequest req;
  req.set_session_id("s");
  req.set_scene("tissue_block");
  hapsim::v1::SessionInfo info;
  ASSERT_TRUE(sessions->CreateSession(&ctx, req, &info).ok());

  int tick_path = 0, others = 0;
  for (const auto& t : CpusOfEachThread()) {
    if (OnTickPath(t.name)) {
      ++tick_path;
      EXPECT_EQ(t.cpus, std::vector<int>{tick_cpu}) << t.name;
    } else {
      ++others;
      EXPECT_EQ(t.cpus, rest) << t.name;
    }
  }
  EXPECT_GE(tick_path, 2) << "the tick worker and DDS's receive threads";
  EXPECT_GE(others, 5) << "gRPC's, the frame pump's, the test's own";
  app.Shutdown();
}

TEST(TickCpusTest, ACpuListIsReadAndABadOneNamed) {
  EXPECT_EQ(common::ParseCpuList("0"), (std::vector<int>{0}));
  EXPECT_EQ(common::ParseCpuList("3,1"), (std::vector<int>{1, 3}));
  EXPECT_EQ(common::ParseCpuList("2-4,0"), (std::vector<int>{0, 2, 3, 4}));
  for (const char* bad : {"", "a", "1,", "3-1", "-1", "1-", "99999", "0x1", " 1"}) {
    EXPECT_FALSE(common::ParseCpuList(bad).has_value()) << '"' << bad << '"';
  }
  const std::vector<int> mine = common::CpusOfThread(0);
  EXPECT_NE(common::CheckTickCpus({CPU_SETSIZE - 1}), "") << "a CPU this process may not use";
  EXPECT_NE(common::CheckTickCpus(mine), "") << "nothing left for the other threads";
  EXPECT_NE(common::CheckTickCpus({}), "");
  if (mine.size() >= 2) {
    EXPECT_EQ(common::CheckTickCpus({mine[0]}), "");
  }
}

TEST(TickCpusTest, AServerGivenCpusItMayNotUseRefusesToStart) {
  ServerOptions o;
  o.listen_address = "127.0.0.1:0";
  o.dds.domain_id = test::ClaimTestDdsDomain();
  o.tick_cpus = {CPU_SETSIZE - 1};
  try {
    ServerApp app(o);
    FAIL() << "started";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--tick-cpus: CPU"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hapsim::service
