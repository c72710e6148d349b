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

// A "haptic" thread calls isolate_calling_thread(keep_others_off) and waits while `check` runs
// in this thread with the processor it was given. Returns whether the haptic thread was pinned
// to that processor alone; `cpu` is the processor (-1 if none).
template <class Check>
bool with_pinned_thread(bool keep_others_off, int* cpu, Check check) {
  std::atomic<int> given{-2};
  std::atomic<bool> checked{false};
  bool pinned = false;
  std::thread haptic([&] {
    const Result<int> r = isolate_calling_thread(keep_others_off);
    const int c = r.ok() ? r.value() : -1;
    cpu_set_t mine;
    CPU_ZERO(&mine);
    (void)pthread_getaffinity_np(pthread_self(), sizeof mine, &mine);
    pinned = c >= 0 && CPU_COUNT(&mine) == 1 && CPU_ISSET(c, &mine);
    given.store(c);
    while (!checked.load()) std::this_thread::yield();
  });
  while (given.load() == -2) std::this_thread::yield();
  *cpu = given.load();
  if (*cpu >= 0) check(*cpu);
  checked.store(true);
  haptic.join();
  return pinned;
}

int processors() {
  cpu_set_t all;
  CPU_ZERO(&all);
  return pthread_getaffinity_np(pthread_self(), sizeof all, &all) == 0 ? CPU_COUNT(&all) : 0;
}

TEST(RealtimeThread, TheIsolatedProcessorIsKeptFromEveryOtherThreadUntilReleased) {
  if (processors() < 2) GTEST_SKIP() << "one processor: nothing to isolate";
  int c = -1;
  const bool pinned = with_pinned_thread(/*keep_others_off=*/true, &c, [](int cpu) {
    EXPECT_FALSE(may_run_on(cpu)) << "this thread still may run on processor " << cpu;
    bool later_thread_may = true;
    std::thread([&] { later_thread_may = may_run_on(cpu); }).join();
    EXPECT_FALSE(later_thread_may) << "a thread started afterwards may run there";
  });
  ASSERT_GE(c, 0);
  EXPECT_TRUE(pinned);
  release_isolated_processor(c);
  EXPECT_TRUE(may_run_on(c));
}

TEST(RealtimeThread, APinnedThreadThatSharesLeavesItsProcessorToTheOthers) {
  if (processors() < 2) GTEST_SKIP() << "one processor: nothing to pin";
  int c = -1;
  const bool pinned = with_pinned_thread(/*keep_others_off=*/false, &c, [](int cpu) {
    EXPECT_TRUE(may_run_on(cpu)) << "this thread was kept off processor " << cpu;
  });
  ASSERT_GE(c, 0);
  EXPECT_TRUE(pinned);
  release_isolated_processor(c);
}

TEST(RealtimeThread, TheSpinIsShortenedOnlyWhereTheHapticThreadSharesItsProcessor) {
  RuntimeSettings s;
  s.spin_ns = 200000;
  s.shared_processor_spin_ns = 50000;
  EXPECT_EQ(haptic_spin_ns(s, /*shares_processor=*/false), 200000);
  EXPECT_EQ(haptic_spin_ns(s, /*shares_processor=*/true), 50000);
  // Never lengthened: a settings' shorter spin stands.
  s.spin_ns = 20000;
  EXPECT_EQ(haptic_spin_ns(s, /*shares_processor=*/true), 20000);
  EXPECT_EQ(haptic_spin_ns(s, /*shares_processor=*/false), 20000);
}

TEST(RealtimeThread, TheProcessorIsKeptOnlyWhereTheRestKeepTwoOrTheThreadIsBestEffort) {
  EXPECT_FALSE(keep_others_off_haptic_processor(2, /*realtime_priority=*/true));
  EXPECT_TRUE(keep_others_off_haptic_processor(2, /*realtime_priority=*/false));
  EXPECT_TRUE(keep_others_off_haptic_processor(3, /*realtime_priority=*/true));
  EXPECT_TRUE(keep_others_off_haptic_processor(8, /*realtime_priority=*/true));
  EXPECT_EQ(allowed_processors(), processors());
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
