// The writer thread: callers never block on it (a full queue drops and
// counts), Flush makes writes visible to anyone opening the file, reads run
// while it commits, and a database error is counted, never thrown.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "hapsim/store/results_store.h"
#include "store_test_util.h"

namespace hapsim::service {
namespace {

using store_test::SampleTrial;
using store_test::TempDir;

// Holds the writer thread inside StoreOptions::before_batch until released.
class WriterGate {
 public:
  void Hold() {
    std::lock_guard lock(mutex_);
    held_ = true;
  }
  void Release() {
    {
      std::lock_guard lock(mutex_);
      held_ = false;
    }
    cv_.notify_all();
  }
  void WaitUntilWriterInside() {
    std::unique_lock lock(mutex_);
    ASSERT_TRUE(cv_.wait_for(lock, std::chrono::seconds(10), [&] { return inside_; }));
  }
  std::function<void()> Hook() {
    return [this] {
      std::unique_lock lock(mutex_);
      inside_ = true;
      cv_.notify_all();
      cv_.wait(lock, [&] { return !held_; });
    };
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool held_ = false, inside_ = false;
};

TEST(ResultsStoreWriter, AFullQueueDropsAndCountsWritesAndNeverBlocksTheCaller) {
  TempDir dir;
  WriterGate gate;  // outlives the store: its destructor needs the gate open
  gate.Hold();
  StoreOptions options;
  options.before_batch = gate.Hook();
  auto store = ResultsStore::Open(dir.File("results.db"), options);
  struct ReleaseOnExit {
    WriterGate& gate;
    ~ReleaseOnExit() { gate.Release(); }
  } release{gate};

  ASSERT_TRUE(store->UpsertTrial(SampleTrial("t1", 0)));
  gate.WaitUntilWriterInside();  // the writer took that one and is stuck before committing it
  constexpr std::size_t kOver = 50;
  const std::size_t submitted = 1 + options.queue_capacity + kOver;
  std::size_t accepted = 1;
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t i = 1; i < submitted; ++i) accepted += store->UpsertTrial(SampleTrial("t1", i)) ? 1 : 0;
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_LT(elapsed, std::chrono::seconds(2));  // 4146 pushes against a stuck writer: no waiting
  EXPECT_EQ(accepted, 1 + options.queue_capacity);
  EXPECT_EQ(store->dropped_writes(), kOver);

  gate.Release();
  store->Flush();
  EXPECT_EQ(store->committed_writes(), 1 + options.queue_capacity);
  EXPECT_EQ(store->dropped_writes() + store->committed_writes(), submitted);
  EXPECT_EQ(store->Trials().size(), 1 + options.queue_capacity);
  EXPECT_EQ(store->write_errors(), 0u);
}

TEST(ResultsStoreWriter, FlushMakesWritesVisibleToASecondOpenOfTheFile) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoreOptions slow;
  slow.batch_interval = std::chrono::seconds(30);  // without Flush nothing would commit for a while
  auto writer = ResultsStore::Open(file, slow);
  writer->UpsertTrial(SampleTrial("t1", 0));  // the first write commits at once (no batch before it)
  writer->Flush();
  writer->UpsertTrial(SampleTrial("t1", 1));
  writer->UpsertSession({"t1", "acupuncture", {}, "alice", "c", "r", 1, ""});
  writer->Flush();                        // must not wait out the 30 s interval
  auto other = ResultsStore::Open(file);  // e.g. hapsim-ctl, or the server after a restart
  EXPECT_EQ(other->Trials().size(), 2u);
  EXPECT_EQ(other->Sessions().size(), 1u);
  EXPECT_EQ(writer->Trials().size(), 2u);
}

TEST(ResultsStoreWriter, DestroyingTheStoreCommitsEverythingQueued) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoreOptions slow;
  slow.batch_interval = std::chrono::seconds(30);
  {
    auto store = ResultsStore::Open(file, slow);
    for (std::uint64_t i = 0; i < 100; ++i) store->UpsertTrial(SampleTrial("t1", i));
  }
  EXPECT_EQ(ResultsStore::Open(file)->Trials().size(), 100u);
}

TEST(ResultsStoreWriter, ReadsRunWhileTheWriterCommits) {
  TempDir dir;
  StoreOptions fast;
  fast.batch_interval = std::chrono::milliseconds(1);
  auto store = ResultsStore::Open(dir.File("results.db"), fast);
  constexpr std::uint64_t kTrials = 3000;
  std::thread writer([&] {
    const std::string sessions[] = {"t0", "t1", "t2", "t3", "t4", "t5", "t6"};
    for (std::uint64_t i = 0; i < kTrials; ++i) {
      while (!store->UpsertTrial(SampleTrial(sessions[i % 7], i))) std::this_thread::yield();
    }
    store->Flush();
  });
  std::size_t last = 0, reads = 0;
  bool monotonic = true;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (last < kTrials && std::chrono::steady_clock::now() < deadline) {
    const std::size_t n = store->Trials().size();  // a committed state each time: never shrinks
    monotonic = monotonic && n >= last;
    last = n;
    ++reads;
  }
  writer.join();
  EXPECT_EQ(last, kTrials);
  EXPECT_TRUE(monotonic);
  EXPECT_GT(reads, 1u);
  EXPECT_EQ(store->write_errors(), 0u);
  EXPECT_EQ(store->dropped_writes(), 0u);
}

TEST(ResultsStoreWriter, ADatabaseErrorIsCountedNotThrownAndTheStoreCarriesOn) {
  TempDir dir;
  const std::string file = dir.File("results.db");
  StoreOptions impatient;
  impatient.busy_timeout = std::chrono::milliseconds(20);
  auto store = ResultsStore::Open(file, impatient);
  store->UpsertTrial(SampleTrial("t1", 0));
  store->Flush();
  ASSERT_EQ(store->write_errors(), 0u);

  sqlite3* other = nullptr;  // another process holding the write lock past the busy timeout
  ASSERT_EQ(sqlite3_open(file.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  store->UpsertTrial(SampleTrial("t1", 1));
  store->Flush();  // returns: the batch failed, it did not hang or throw
  EXPECT_GE(store->write_errors(), 1u);
  EXPECT_EQ(store->Trials().size(), 1u);  // reads still work (WAL: the lock holder wrote nothing)
  sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(other);

  const std::uint64_t errors = store->write_errors();
  store->UpsertTrial(SampleTrial("t1", 2));
  store->Flush();
  EXPECT_EQ(store->write_errors(), errors);
  EXPECT_EQ(store->Trials().size(), 2u);  // trial 1's batch is lost, trial 2's made it
}

}  // namespace
}  // namespace hapsim::service
