#include "tests/support/small_disk.h"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace lap::test {
namespace {

/// The child's exit code when it could not mount the disk; its reason goes to the pipe.
constexpr int kCannotMount = 77;
/// Its exit code when the body threw.
constexpr int kBodyThrew = 70;
/// How long the child may run [s] before SIGALRM ends it.
constexpr unsigned kChildSeconds = 300;

/// Writes a /proc file; "" or why not (errno taken at once).
std::string write_text(const char* file, const std::string& text) {
  const int fd = ::open(file, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return std::string(file) + ": " + std::strerror(errno);
  const ssize_t n = ::write(fd, text.data(), text.size());
  const int reason = errno;
  ::close(fd);
  if (n == static_cast<ssize_t>(text.size())) return "";
  return std::string(file) + ": " + (n < 0 ? std::strerror(reason) : "short write");
}

/// A mount namespace of the child's own: directly as root, or inside a new user namespace that
/// maps the caller to root (unprivileged, where the kernel allows it). "" or why not.
std::string own_mount_namespace() {
  if (::unshare(CLONE_NEWNS) == 0) return "";
  const int first = errno;
  const uid_t uid = ::geteuid();
  const gid_t gid = ::getegid();
  if (::unshare(CLONE_NEWUSER | CLONE_NEWNS) != 0) {
    const int second = errno;
    return std::string("unshare(CLONE_NEWNS): ") + std::strerror(first) +
           "; with CLONE_NEWUSER: " + std::strerror(second);
  }
  std::string why = write_text("/proc/self/setgroups", "deny");
  if (why.empty()) why = write_text("/proc/self/uid_map", "0 " + std::to_string(uid) + " 1");
  if (why.empty()) why = write_text("/proc/self/gid_map", "0 " + std::to_string(gid) + " 1");
  return why.empty() ? "" : "cannot map the user namespace: " + why;
}

std::string mount_small_disk(const std::filesystem::path& at, size_t bytes) {
  std::string why = own_mount_namespace();
  if (!why.empty()) return why;
  // Private, so that nothing mounted here shows in the parent's namespace.
  if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) {
    const int reason = errno;
    return std::string("mount --make-rprivate /: ") + std::strerror(reason);
  }
  const std::string size = "size=" + std::to_string(bytes);
  if (::mount("tmpfs", at.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, size.c_str()) != 0) {
    const int reason = errno;
    return std::string("mount -t tmpfs: ") + std::strerror(reason);
  }
  return "";
}

}  // namespace

SmallDiskRun run_on_a_small_disk(const std::filesystem::path& mount_point, size_t bytes,
                                 const std::function<int()>& body) {
  SmallDiskRun run;
  int reason[2];
  if (::pipe2(reason, O_CLOEXEC) != 0) {
    run.why_not = std::string("pipe: ") + std::strerror(errno);
    return run;
  }
  std::fflush(nullptr);  // nothing buffered twice
  const pid_t child = ::fork();
  if (child < 0) {
    run.why_not = std::string("fork: ") + std::strerror(errno);
    ::close(reason[0]);
    ::close(reason[1]);
    return run;
  }
  if (child == 0) {
    // Never outliving the test, nor running for ever (a filler loop on the wrong disk).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    ::alarm(kChildSeconds);
    ::close(reason[0]);
    const std::string why = mount_small_disk(mount_point, bytes);
    if (!why.empty()) {
      (void)::write(reason[1], why.data(), why.size());
      ::_exit(kCannotMount);
    }
    ::close(reason[1]);
    // An exception must not reach gtest in the child (it would go on with the parent's tests).
    int code = kBodyThrew;
    try {
      code = body();
    } catch (...) {
    }
    std::fflush(nullptr);
    ::_exit(code);  // no atexit handlers, no gtest teardown in the child
  }
  ::close(reason[1]);
  char text[512];
  ssize_t n = 0;
  std::string why;
  while ((n = ::read(reason[0], text, sizeof text)) > 0 || (n < 0 && errno == EINTR)) {
    if (n > 0) why.append(text, static_cast<size_t>(n));
  }
  ::close(reason[0]);
  int status = 0;
  pid_t waited = 0;
  while ((waited = ::waitpid(child, &status, 0)) < 0 && errno == EINTR) {
  }
  if (waited != child) {
    run.ran = true;  // it did start: a failure, not a skip
    run.exit_code = -1;
    return run;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kCannotMount && !why.empty()) {
    run.why_not = why;
    return run;
  }
  run.ran = true;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

void fill_the_disk(const std::filesystem::path& filler, size_t bytes) {
  std::ofstream out(filler, std::ios::binary);
  const std::string block(4096, 'x');
  const size_t most = bytes / block.size() + 2;
  for (size_t k = 0;
       k < most && out.write(block.data(), static_cast<std::streamsize>(block.size())).flush();
       ++k) {
  }
}

}  // namespace lap::test
