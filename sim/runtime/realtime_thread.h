#pragma once
/// \file
/// Scheduling helpers for the loops (thesis §3.2: the servo loop must keep its rate): ask for
/// SCHED_FIFO and locked memory when permitted, and sleep to an absolute time on the monotonic
/// clock (clock_nanosleep with TIMER_ABSTIME, then a short spin for the last stretch).

#include <cstdint>
#include <string>

#include "core/result.h"

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

/// Gives the calling thread a processor of its own within this process: pins it to the last
/// processor it may run on and takes that processor from every other thread of the process
/// (threads started later inherit their starter's set, so a renderer's worker threads stay off
/// it too). Nothing is done with fewer than two processors. Returns the processor, or why not.
/// Setup: reads /proc/self/task and allocates.
[[nodiscard]] Result<int> isolate_calling_thread();
/// Gives processor `cpu` (isolate_calling_thread()'s) back to every thread of the process, the
/// calling one included: the end of a session that isolated its haptic thread.
void release_isolated_processor(int cpu);

}  // namespace lap::sim
