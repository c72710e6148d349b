#pragma once
/// \file
/// A disk that really fills up: a small tmpfs mounted in a child process's own mount namespace,
/// so that a write runs out of space with the kernel's ENOSPC (not RLIMIT_FSIZE's EFBIG) and the
/// mount vanishes with the child, whatever the test does.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

namespace lap::test {

/// What became of a body run on a small disk.
struct SmallDiskRun {
  bool ran = false;     ///< false: no disk could be mounted here (`why_not` says why); skip
  int exit_code = -1;   ///< the body's return value (or 128 + the signal that ended the child)
  std::string why_not;  ///< why the disk could not be mounted
};

/// Forks; the child takes a mount namespace of its own (as root; otherwise a user namespace too,
/// where the kernel allows it), mounts a tmpfs of `bytes` at `mount_point` (an existing empty
/// folder) and returns `body()`'s value as its exit code (70 if it threw; 128 + the signal that
/// ended it, SIGALRM after 300 s). The body runs in the child: its gtest assertions would be lost,
/// so it writes what the parent should check to files outside `mount_point`, which the child sees
/// as the parent does. Call it from a single-threaded process (ctest runs one test a process): a
/// child forked from threads cannot take a user namespace, and under ThreadSanitizer it may not
/// start threads.
[[nodiscard]] SmallDiskRun run_on_a_small_disk(const std::filesystem::path& mount_point,
                                               size_t bytes, const std::function<int()>& body);

/// Fills the rest of a small disk of `bytes` (in the body above) with the file `filler`: blocks
/// of 4 KB until a write fails, and never more than the disk's blocks and two (so never for
/// ever on a disk that is not full).
void fill_the_disk(const std::filesystem::path& filler, size_t bytes);

}  // namespace lap::test
