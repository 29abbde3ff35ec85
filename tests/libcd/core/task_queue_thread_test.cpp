// TaskQueueThread (worker_thread.hpp): tasks run in the order handed, off the
// handing thread, wait() sees them all done and wait_for(ticket) those up to
// the ticket's, and a task that throws is rethrown once with the tasks after
// it dropped; WorkerThread runs its tasks in turn, each future holding its
// own task's error.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <stdexcept>
#include <thread>
#include <vector>

#include "libcd/core/worker_thread.hpp"

namespace snag {
namespace {

TEST(TaskQueueThread, RunsTasksInTheOrderHandedOffTheCallersThread) {
  TaskQueueThread queue;
  std::vector<int> order;  // only the queue's thread touches it till wait()
  std::atomic<bool> off_caller{true};
  const std::thread::id caller = std::this_thread::get_id();
  for (int round = 0; round < 50; ++round) {
    for (int k = 0; k < 20; ++k) {
      queue.post([&, k, round] {
        if (std::this_thread::get_id() == caller) off_caller = false;
        if (k == 0) std::this_thread::sleep_for(std::chrono::microseconds(round % 5));
        order.push_back(round * 20 + k);
      });
    }
    if (round % 7 == 0) queue.wait();
  }
  queue.wait();
  ASSERT_EQ(order.size(), 1000u);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(order[i], i);
  EXPECT_TRUE(off_caller);
}

TEST(TaskQueueThread, WaitSeesSlowTasksDone) {
  TaskQueueThread queue;
  std::atomic<int> done{0};
  for (int k = 0; k < 3; ++k) {
    queue.post([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      ++done;
    });
  }
  queue.wait();
  EXPECT_EQ(done.load(), 3);
  queue.wait();  // nothing handed: returns at once
}

TEST(TaskQueueThread, WaitForATicketWaitsForItsTaskAndThoseBeforeOnly) {
  TaskQueueThread queue;
  std::atomic<int> done{0};
  std::promise<void> gate;
  std::shared_future<void> open = gate.get_future().share();
  const std::uint64_t first = queue.post([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ++done;
  });
  const std::uint64_t second = queue.post([&] { ++done; });
  const std::uint64_t held = queue.post([&, open] {
    open.wait();
    ++done;
  });
  EXPECT_LT(first, second);
  EXPECT_LT(second, held);
  queue.wait_for(second);  // returns while the third is held at its gate
  EXPECT_EQ(done.load(), 2);
  gate.set_value();
  queue.wait_for(held);
  EXPECT_EQ(done.load(), 3);
  queue.wait_for(first);  // long done: returns at once
}

TEST(TaskQueueThread, RethrowsTheFirstErrorOnceAndDropsTheTasksAfterIt) {
  TaskQueueThread queue;
  std::vector<int> ran;
  std::promise<void> gate;  // holds the thread till all three are queued
  std::shared_future<void> open = gate.get_future().share();
  queue.post([&, open] {
    open.wait();
    ran.push_back(1);
  });
  queue.post([&] { throw std::runtime_error("first"); });
  queue.post([&] { ran.push_back(3); });
  gate.set_value();
  EXPECT_THROW(
      {
        try {
          queue.wait();
        } catch (const std::runtime_error& error) {
          EXPECT_STREQ(error.what(), "first");
          throw;
        }
      },
      std::runtime_error);
  EXPECT_EQ(ran, std::vector<int>{1});
  queue.post([&] { ran.push_back(4); });  // usable again after the error
  EXPECT_NO_THROW(queue.wait());
  EXPECT_EQ(ran, (std::vector<int>{1, 4}));
}

TEST(TaskQueueThread, RunsWhatIsQueuedBeforeItGoes) {
  std::atomic<int> done{0};
  {
    TaskQueueThread queue;
    for (int k = 0; k < 10; ++k) {
      queue.post([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ++done;
      });
    }
  }
  EXPECT_EQ(done.load(), 10);
}

TEST(WorkerThread, RunsTasksInTurnAndEachFutureHoldsItsOwnError) {
  WorkerThread worker;
  std::vector<int> ran;
  std::future<void> first = worker.run([&] { ran.push_back(1); });
  std::future<void> failing = worker.run([] { throw std::runtime_error("second"); });
  std::future<void> third = worker.run([&] { ran.push_back(3); });  // not dropped: the error is the future's
  EXPECT_NO_THROW(first.get());
  EXPECT_THROW(failing.get(), std::runtime_error);
  EXPECT_NO_THROW(third.get());
  EXPECT_EQ(ran, (std::vector<int>{1, 3}));
}

}  // namespace
}  // namespace snag
