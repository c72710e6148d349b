#pragma once
/// \file
/// The project's one error type: a problem found in an input or a set-up, with where it is
/// (file, line, field) and what was expected. Every loader, builder and `create` reports its
/// problems as Diagnostics (core/result.h); the command line and the application print them with
/// to_string(), so a user sees the same words wherever a problem shows.

#include <cstdio>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lap {

/// One problem, printed as `file:line: field: message` (parts that do not apply are left out).
struct Diagnostic {
  std::string file;     ///< the input file, or "" when none applies
  int line = 0;         ///< 1-based; 0 when no line applies
  std::string field;    ///< dotted path (e.g. organs[1].material.stiffness_n_per_m), or ""
  std::string message;  ///< what is wrong and what was expected

  /// `file:line: field: message`.
  [[nodiscard]] std::string to_string() const {
    std::string s;
    if (!file.empty()) {
      s += file;
      if (line > 0) s += ":" + std::to_string(line);
      s += ": ";
    }
    if (!field.empty()) s += field + ": ";
    return s + message;
  }
};

/// A problem with no file or field (a set-up error in the caller's own values).
[[nodiscard]] inline Diagnostic diagnostic(std::string message) {
  Diagnostic d;
  d.message = std::move(message);
  return d;
}

/// A problem with a file (and a line where one applies).
[[nodiscard]] inline Diagnostic file_diagnostic(std::string file, int line, std::string field,
                                                std::string message) {
  return Diagnostic{std::move(file), line, std::move(field), std::move(message)};
}

/// Text from an input, quoted for a message: in single quotes, at most `max_chars` of it (then
/// `...` and how long it was), control bytes escaped (\n, \t, \xNN) so that a message stays one
/// line, and never cut inside a UTF-8 character. A message must never carry a whole foreign
/// document (issue 25: a recording naming /etc/passwd as its scenario had it printed whole).
[[nodiscard]] inline std::string quote_excerpt(std::string_view text, size_t max_chars = 60) {
  size_t end = text.size() <= max_chars ? text.size() : max_chars;
  if (end < text.size()) {
    // Back off UTF-8 continuation bytes (10xxxxxx) so that the cut falls between characters.
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0U) == 0x80U) --end;
  }
  std::string s = "'";
  for (const char c : text.substr(0, end)) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') {
      s += "\\n";
    } else if (c == '\t') {
      s += "\\t";
    } else if (u < 0x20 || u == 0x7F) {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", static_cast<unsigned>(u));
      s += hex;
    } else {
      s += c;
    }
  }
  if (end < text.size()) return s + "...' (" + std::to_string(text.size()) + " bytes)";
  return s + "'";
}

/// Every diagnostic on its own line.
[[nodiscard]] inline std::string to_string(const std::vector<Diagnostic>& diagnostics) {
  std::string s;
  for (const Diagnostic& d : diagnostics) {
    if (!s.empty()) s += "\n";
    s += d.to_string();
  }
  return s;
}

}  // namespace lap
