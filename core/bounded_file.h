#pragma once
/// \file
/// Reading a file a user named, whole, within a size limit. Every reader of untrusted input goes
/// through here first (issue 25): `/dev/zero` or `/dev/urandom` never ends, a FIFO blocks its
/// reader until someone writes, a folder cannot be read, and a file of gigabytes would be read
/// into memory before any check looked at it. Each is refused with a message that names the
/// file and says what was expected; nothing is opened but a regular file, and never more than
/// `max_bytes + 1` bytes are read (a file the kernel says is empty, as /proc's are, or one that
/// grows while it is read, is cut off there and refused).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

#include "core/diagnostic.h"
#include "core/result.h"

namespace lap {

/// What a path is, in words for a message ("a folder", "a FIFO"...).
[[nodiscard]] inline std::string describe_file_type(std::filesystem::file_type type) {
  using std::filesystem::file_type;
  switch (type) {
    case file_type::directory:
      return "a folder";
    case file_type::character:
      return "a character device";
    case file_type::block:
      return "a block device";
    case file_type::fifo:
      return "a FIFO (named pipe)";
    case file_type::socket:
      return "a socket";
    case file_type::regular:
      return "a regular file";
    default:
      return "not a regular file";
  }
}

/// Whether `file` is a regular file (through symbolic links) of at most `max_bytes`; else why
/// not, naming the file: `what` says what the file was meant to be ("a YAML scenario file"),
/// `limit_source` where the limit is defined, if the message should say.
[[nodiscard]] inline Status check_regular_file(const std::filesystem::path& file,
                                               std::uintmax_t max_bytes, std::string_view what,
                                               std::string_view limit_source = {}) {
  const std::string source =
      limit_source.empty() ? std::string() : " (" + std::string(limit_source) + ")";
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(file, ec);
  if (status.type() == std::filesystem::file_type::not_found) {
    return file_diagnostic(file.string(), 0, "", "not found (expected " + std::string(what) + ")");
  }
  if (ec) {
    return file_diagnostic(
        file.string(), 0, "",
        "cannot be read (" + ec.message() + "; expected " + std::string(what) + ")");
  }
  if (status.type() != std::filesystem::file_type::regular) {
    return file_diagnostic(file.string(), 0, "",
                           "is " + describe_file_type(status.type()) + "; expected " +
                               std::string(what) + ", a regular file");
  }
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) {
    return file_diagnostic(
        file.string(), 0, "",
        "cannot be read (" + ec.message() + "; expected " + std::string(what) + ")");
  }
  if (size > max_bytes) {
    return file_diagnostic(file.string(), 0, "",
                           "file of " + std::to_string(size) +
                               " bytes is larger than the limit of " + std::to_string(max_bytes) +
                               " for " + std::string(what) + source);
  }
  return {};
}

/// The whole of `file`, a regular file of at most `max_bytes` (check_regular_file's messages),
/// read in binary.
[[nodiscard]] inline Result<std::string> read_bounded_file(const std::filesystem::path& file,
                                                           std::uintmax_t max_bytes,
                                                           std::string_view what,
                                                           std::string_view limit_source = {}) {
  if (Status ok = check_regular_file(file, max_bytes, what, limit_source); !ok.ok()) {
    return ok.diagnostics();
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    return file_diagnostic(file.string(), 0, "",
                           "cannot be opened for reading (expected " + std::string(what) + ")");
  }
  std::string bytes;
  char buffer[65536];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) {
    bytes.append(buffer, static_cast<size_t>(in.gcount()));
    if (bytes.size() > max_bytes) {  // grew after it was measured, or its size was not its length
      return file_diagnostic(
          file.string(), 0, "",
          "holds more than the limit of " + std::to_string(max_bytes) + " bytes for " +
              std::string(what) + " (" +
              (limit_source.empty() ? "it grew while being read" : std::string(limit_source)) +
              ")");
    }
  }
  if (in.bad()) {
    return file_diagnostic(file.string(), 0, "",
                           "reading failed (expected " + std::string(what) + ")");
  }
  return bytes;
}

}  // namespace lap
