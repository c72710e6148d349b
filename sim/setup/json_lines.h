#pragma once
/// \file
/// Lines for the fields of a JSON document, so that a problem in a text .gltf or a session.json
/// can be named `file:line: buffers[0].uri: ...` as a YAML scenario's are. nlohmann::json (3.11,
/// Debian 12) keeps no positions in the values it builds, so the text is read a second time with
/// its SAX parser through an input iterator that counts lines as the parser consumes bytes: when
/// the parser reports a key, its last byte read is the key's closing quote, so the count is the
/// key's line. Paths are recorded down to `max_depth` levels and up to `max_entries` of them, so
/// that a mutated document of a million entries costs no more than a small one.

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>

namespace lap::sim {

class JsonLines {
 public:
  /// Scans `text`. A text that is not JSON keeps the paths before the error, and the error's
  /// line and message.
  static JsonLines scan(std::string_view text, int max_depth = 3, size_t max_entries = 4096);

  /// The line (1-based) where the field at `path` (`scene`, `buffers[0].uri`: its key, or an
  /// array element's first byte) is; `fallback` when it was not recorded.
  [[nodiscard]] int line(const std::string& path, int fallback = 0) const;

  [[nodiscard]] bool parsed() const { return error_.empty(); }
  /// Where the text stops being JSON, and why (nlohmann's words without its prefix).
  [[nodiscard]] int error_line() const { return error_line_; }
  [[nodiscard]] const std::string& error() const { return error_; }

 private:
  friend class JsonLinesHandler;
  std::unordered_map<std::string, int> lines_;
  int error_line_ = 0;
  std::string error_;
};

}  // namespace lap::sim
