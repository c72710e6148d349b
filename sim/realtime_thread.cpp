#include "sim/realtime_thread.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <cerrno>
#include <cstring>

namespace lap::sim {

int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

void sleep_until_ns(int64_t deadline_ns, int64_t spin_ns) noexcept {
  const int64_t wake = deadline_ns - spin_ns;
  if (wake > monotonic_ns()) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(wake / 1000000000LL);
    ts.tv_nsec = static_cast<long>(wake % 1000000000LL);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
  while (monotonic_ns() < deadline_ns) {
  }
}

std::string request_realtime_priority(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
  if (rc == 0) return {};
  return std::string("SCHED_FIFO refused (") + std::strerror(rc) +
         "): running best effort; grant it with `ulimit -r` / CAP_SYS_NICE";
}

std::string lock_memory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return {};
  return std::string("mlockall refused (") + std::strerror(errno) +
         "): memory not locked; raise `ulimit -l` to lock it";
}

}  // namespace lap::sim
