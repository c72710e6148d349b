#pragma once
/// \file
/// Writing a file whole or not at all: the bytes go to a temporary file of this process's own
/// beside it, are synced to the disk, and only then take the file's name. A full disk, a quota or
/// a failing device leaves no half-written file (and an older file of that name as it was), and
/// the diagnostic names the file and the system's reason (issue 25: "the disk full while
/// recording"). POSIX (mkstemp, fsync, rename) besides the standard library.

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/diagnostic.h"
#include "core/result.h"

namespace lap {

/// Writes `bytes` as `file` (replacing a file of that name), whole or not at all; `what` names
/// the contents in the message ("the device recording"). Mode 0600: what it writes is a
/// trainee's.
[[nodiscard]] inline Status write_file_whole(const std::filesystem::path& file,
                                             std::string_view bytes, const std::string& what) {
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
  std::string temporary = (dir / ("." + file.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) {
    return file_diagnostic(file.string(), 0, "",
                           "cannot write " + what + ": " + std::strerror(errno));
  }
  size_t done = 0;
  bool written = true;
  while (written && done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    written = n > 0;
    if (written) done += static_cast<size_t>(n);
  }
  written = written && ::fsync(fd) == 0;
  const int reason = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed || ::rename(temporary.c_str(), file.c_str()) != 0) {
    const int why = !written ? reason : errno;
    ::unlink(temporary.c_str());
    return file_diagnostic(
        file.string(), 0, "",
        "cannot write " + what + ": " + std::strerror(why) + " (nothing of it was written)");
  }
  return {};
}

}  // namespace lap
