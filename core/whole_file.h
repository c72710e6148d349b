#pragma once
/// \file
/// Writing a file whole or not at all: the bytes go to a temporary file of this process's own
/// beside it, are synced to the disk, and only then take the file's name (the folder's entry
/// synced too). A full disk, a quota or a failing device leaves no half-written file (and an
/// older file of that name as it was), and the diagnostic names the file and the system's reason
/// (issue 25: "the disk full while recording"). POSIX (mkostemp, fsync, rename; Linux's
/// renameat2 for a file never written over another) besides the standard library.

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>  // renameat2, RENAME_NOREPLACE (glibc, _GNU_SOURCE)
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/diagnostic.h"
#include "core/result.h"

namespace lap {

/// What becomes of a file already of that name.
enum class IfTaken {
  kReplace,  ///< the new file takes its place, at once (rename)
  kRefuse,   ///< it stays, and the new one is not written ("already exists: WHAT is written once")
};

/// Renames `temporary` to `file`: over a file of that name, or (kRefuse) never over one, with
/// RENAME_NOREPLACE where the file system has it, else a check and a plain rename. 0 or errno.
[[nodiscard]] inline int move_into_place(const std::string& temporary,
                                         const std::filesystem::path& file, IfTaken if_taken) {
  if (if_taken == IfTaken::kReplace) {
    return ::rename(temporary.c_str(), file.c_str()) == 0 ? 0 : errno;
  }
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, file.c_str(), RENAME_NOREPLACE) == 0) {
    return 0;
  }
  if (errno != EINVAL && errno != ENOSYS) return errno;  // no RENAME_NOREPLACE there
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::symlink_status(file, ec))) return EEXIST;
  return ::rename(temporary.c_str(), file.c_str()) == 0 ? 0 : errno;
}

/// Writes `bytes` as `file`, whole or not at all; `what` names the contents in the message ("the
/// device recording"). Mode 0600: what it writes is a trainee's.
[[nodiscard]] inline Status write_file_whole(const std::filesystem::path& file,
                                             std::string_view bytes, const std::string& what,
                                             IfTaken if_taken = IfTaken::kReplace) {
  // `taken`: the name was found taken as the file was put in place (not a temporary name).
  auto failed = [&](int reason, bool taken = false) -> Status {
    if (taken) {
      return file_diagnostic(file.string(), 0, "", "already exists: " + what + " is written once");
    }
    return file_diagnostic(
        file.string(), 0, "",
        "cannot write " + what + ": " + std::strerror(reason) + " (nothing of it was written)");
  };
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  std::string temporary = (dir / ("." + file.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkostemp(temporary.data(), O_CLOEXEC);
  if (fd < 0) return failed(errno);
  size_t done = 0;
  int reason = 0;
  while (reason == 0 && done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
    } else if (n < 0 && errno != EINTR) {
      reason = errno;
    } else if (n == 0) {
      reason = EIO;  // no progress and no reason given
    }
  }
  if (reason == 0 && ::fsync(fd) != 0) reason = errno;
  if (::close(fd) != 0 && reason == 0) reason = errno;
  bool taken = false;
  if (reason == 0) {
    reason = move_into_place(temporary, file, if_taken);
    taken = reason == EEXIST && if_taken == IfTaken::kRefuse;
  }
  if (reason != 0) {
    ::unlink(temporary.c_str());
    return failed(reason, taken);
  }
  // The folder's entry on the disk too (best effort: some file systems refuse a folder's sync).
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
  return {};
}

}  // namespace lap
