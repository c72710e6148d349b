#include "sim/runtime/realtime_thread.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

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

namespace {

// Adds processor `cpu` to, or takes it from, every thread of this process but the calling one
// (a thread left with no processor keeps its set).
void set_cpu_of_other_threads(int cpu, bool allowed) {
  const auto self = static_cast<pid_t>(syscall(SYS_gettid));
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", ec)) {
    const std::string name = entry.path().filename().string();
    char* end = nullptr;
    const long tid = std::strtol(name.c_str(), &end, 10);
    if (end == name.c_str() || *end != '\0' || tid == self) continue;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(static_cast<pid_t>(tid), sizeof set, &set) != 0) continue;
    if (allowed) {
      CPU_SET(cpu, &set);
    } else {
      CPU_CLR(cpu, &set);
    }
    if (CPU_COUNT(&set) > 0) (void)sched_setaffinity(static_cast<pid_t>(tid), sizeof set, &set);
  }
}

}  // namespace

bool keep_others_off_haptic_processor(int processors, bool realtime_priority) {
  return processors >= 3 || !realtime_priority;
}

int64_t haptic_spin_ns(const RuntimeSettings& settings, bool shares_processor) {
  if (!shares_processor) return settings.spin_ns;
  return std::min(settings.spin_ns, settings.shared_processor_spin_ns);
}

int allowed_processors() {
  cpu_set_t mine;
  CPU_ZERO(&mine);
  if (pthread_getaffinity_np(pthread_self(), sizeof mine, &mine) != 0) return 1;
  return CPU_COUNT(&mine);
}

Result<int> isolate_calling_thread(bool keep_others_off) {
  cpu_set_t mine;
  CPU_ZERO(&mine);
  if (pthread_getaffinity_np(pthread_self(), sizeof mine, &mine) != 0 || CPU_COUNT(&mine) < 2) {
    return diagnostic("fewer than two processors: the haptic thread shares them");
  }
  int cpu = -1;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &mine)) cpu = c;
  }
  cpu_set_t only;
  CPU_ZERO(&only);
  CPU_SET(cpu, &only);
  if (const int rc = pthread_setaffinity_np(pthread_self(), sizeof only, &only); rc != 0) {
    return diagnostic(std::string("could not pin the haptic thread (") + std::strerror(rc) + ")");
  }
  if (keep_others_off) set_cpu_of_other_threads(cpu, false);
  return cpu;
}

void release_isolated_processor(int cpu) {
  if (cpu < 0) return;
  set_cpu_of_other_threads(cpu, true);
  cpu_set_t self;
  CPU_ZERO(&self);
  if (sched_getaffinity(0, sizeof self, &self) == 0) {
    CPU_SET(cpu, &self);
    (void)sched_setaffinity(0, sizeof self, &self);
  }
}

}  // namespace lap::sim
