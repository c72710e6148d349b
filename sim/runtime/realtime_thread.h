#pragma once
/// \file
/// Scheduling helpers for the loops (thesis §3.2: the servo loop must keep its rate): ask for
/// SCHED_FIFO and locked memory when permitted, and sleep to an absolute time on the monotonic
/// clock (clock_nanosleep with TIMER_ABSTIME, then a short spin for the last stretch).

#include <cstdint>
#include <string>

#include "core/result.h"
#include "sim/setup/runtime_settings.h"

namespace lap::sim {

/// Monotonic time [ns].
[[nodiscard]] int64_t monotonic_ns() noexcept;

/// Sleeps until `deadline_ns` (monotonic): a kernel sleep to spin_ns before it, then a spin.
void sleep_until_ns(int64_t deadline_ns, int64_t spin_ns) noexcept;

/// Asks for SCHED_FIFO at `priority` for the calling thread. Returns an empty string, or the
/// reason it was refused (the thread then runs best effort).
[[nodiscard]] std::string request_realtime_priority(int priority);

/// Locks the process's memory (mlockall) so the haptic loop takes no page faults. Returns an
/// empty string or the reason it was refused.
[[nodiscard]] std::string lock_memory();

/// Pins the calling thread to the last processor it may run on. With `keep_others_off` that
/// processor becomes its own within this process: it is taken from every other thread of the
/// process (threads started later inherit their starter's set, so a renderer's worker threads
/// stay off it too). Nothing is done with fewer than two processors. Returns the processor, or
/// why not. Setup: reads /proc/self/task and allocates.
[[nodiscard]] Result<int> isolate_calling_thread(bool keep_others_off = true);
/// Whether the haptic thread should keep its processor from the other threads
/// (isolate_calling_thread's `keep_others_off`): yes when the process has three processors or
/// more (the rest keep two), or when the haptic thread has no SCHED_FIFO (a best-effort thread
/// would wait for the others' time slices). With two processors and SCHED_FIFO no: the haptic
/// thread preempts whatever runs there the moment it wakes, and the renderer keeps both
/// processors (a software-rendered frame took 1.5 times as long on one: docs/benchmarks.md).
[[nodiscard]] bool keep_others_off_haptic_processor(int processors, bool realtime_priority);
/// The haptic loop's spin before each deadline (sleep_until_ns): settings.spin_ns, or the
/// shorter settings.shared_processor_spin_ns when the thread shares its processor with the
/// others (isolated without keep_others_off), where the spin's time is the renderer's loss.
[[nodiscard]] int64_t haptic_spin_ns(const RuntimeSettings& settings, bool shares_processor);
/// The processors the calling thread may run on.
[[nodiscard]] int allowed_processors();
/// Gives processor `cpu` (isolate_calling_thread()'s) back to every thread of the process, the
/// calling one included: the end of a session that isolated its haptic thread.
void release_isolated_processor(int cpu);

}  // namespace lap::sim
