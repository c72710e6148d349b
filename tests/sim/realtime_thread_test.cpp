// The haptic thread's processor (realtime_thread.h): while it is isolated, no other thread of
// the process may run there, threads started afterwards included; released, they all may again.
// Pinned without isolation, the others keep it.

#include "sim/runtime/realtime_thread.h"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <string>
#include <thread>

namespace lap::sim {
namespace {

bool may_run_on(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  return pthread_getaffinity_np(pthread_self(), sizeof set, &set) == 0 && CPU_ISSET(cpu, &set);
}

TEST(RealtimeThread, TheIsolatedProcessorIsKeptFromEveryOtherThreadUntilReleased) {
  cpu_set_t all;
  CPU_ZERO(&all);
  ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof all, &all), 0);
  if (CPU_COUNT(&all) < 2) GTEST_SKIP() << "one processor: nothing to isolate";
  std::atomic<int> cpu{-2};
  std::atomic<bool> checked{false};
  bool haptic_pinned = false;
  std::thread haptic([&] {
    const Result<int> isolated = isolate_calling_thread();
    const int c = isolated.ok() ? isolated.value() : -1;
    cpu_set_t mine;
    CPU_ZERO(&mine);
    (void)pthread_getaffinity_np(pthread_self(), sizeof mine, &mine);
    haptic_pinned = c >= 0 && CPU_COUNT(&mine) == 1 && CPU_ISSET(c, &mine);
    cpu.store(c);
    while (!checked.load()) std::this_thread::yield();
  });
  while (cpu.load() == -2) std::this_thread::yield();
  const int c = cpu.load();
  ASSERT_GE(c, 0);
  EXPECT_FALSE(may_run_on(c)) << "this thread still may run on processor " << c;
  bool later_thread_may = true;
  std::thread([&] { later_thread_may = may_run_on(c); }).join();
  EXPECT_FALSE(later_thread_may) << "a thread started afterwards may run there";
  checked.store(true);
  haptic.join();
  EXPECT_TRUE(haptic_pinned);
  release_isolated_processor(c);
  EXPECT_TRUE(may_run_on(c));
}

TEST(RealtimeThread, APinnedThreadThatSharesLeavesItsProcessorToTheOthers) {
  cpu_set_t all;
  CPU_ZERO(&all);
  ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof all, &all), 0);
  if (CPU_COUNT(&all) < 2) GTEST_SKIP() << "one processor: nothing to pin";
  std::atomic<int> cpu{-2};
  std::atomic<bool> checked{false};
  bool haptic_pinned = false;
  std::thread haptic([&] {
    const Result<int> pinned = isolate_calling_thread(/*keep_others_off=*/false);
    const int c = pinned.ok() ? pinned.value() : -1;
    cpu_set_t mine;
    CPU_ZERO(&mine);
    (void)pthread_getaffinity_np(pthread_self(), sizeof mine, &mine);
    haptic_pinned = c >= 0 && CPU_COUNT(&mine) == 1 && CPU_ISSET(c, &mine);
    cpu.store(c);
    while (!checked.load()) std::this_thread::yield();
  });
  while (cpu.load() == -2) std::this_thread::yield();
  const int c = cpu.load();
  ASSERT_GE(c, 0);
  EXPECT_TRUE(may_run_on(c)) << "this thread was kept off processor " << c;
  checked.store(true);
  haptic.join();
  EXPECT_TRUE(haptic_pinned);
}

TEST(RealtimeThread, TheProcessorIsKeptOnlyWhereTheRestKeepTwoOrTheThreadIsBestEffort) {
  EXPECT_FALSE(keep_others_off_haptic_processor(2, /*realtime_priority=*/true));
  EXPECT_TRUE(keep_others_off_haptic_processor(2, /*realtime_priority=*/false));
  EXPECT_TRUE(keep_others_off_haptic_processor(3, /*realtime_priority=*/true));
  EXPECT_TRUE(keep_others_off_haptic_processor(8, /*realtime_priority=*/true));
  cpu_set_t mine;
  CPU_ZERO(&mine);
  ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof mine, &mine), 0);
  EXPECT_EQ(allowed_processors(), CPU_COUNT(&mine));
  std::thread([] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(0, &one);
    if (pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0) {
      EXPECT_EQ(allowed_processors(), 1);
    }
  }).join();
}

}  // namespace
}  // namespace lap::sim
