#include "sim/setup/mesh_text_lines.h"

#include <locale.h>
#include <stdlib.h>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace lap::sim::mesh_text {

std::string shown(std::string_view token) {
  std::string s;
  for (char c : token.substr(0, 32)) {
    const auto u = static_cast<unsigned char>(c);
    s += (u >= 0x20 && u < 0x7F) ? c : '?';
  }
  if (token.size() > 32) s += "...";
  return s;
}

std::string hex_byte(char c) {
  char buf[3];
  std::snprintf(buf, sizeof(buf), "%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
  return buf;
}

std::optional<double> number_value(std::string_view token) {
  static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", nullptr);
  const std::string s(token);
  char* end = nullptr;
  const double v = strtod_l(s.c_str(), &end, c_locale);
  if (end == s.c_str() || end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

Problem number_problem(std::string_view token, const std::string& what) {
  const std::optional<double> v = number_value(token);
  if (!v) return what + " '" + shown(token) + "' is not a number";
  if (!std::isfinite(*v)) return what + " '" + shown(token) + "' is not a finite number";
  return std::nullopt;
}

std::optional<int64_t> whole_number(std::string_view token) {
  int64_t v = 0;
  const char* end = token.data() + token.size();
  const auto r = std::from_chars(token.data(), end, v);
  if (r.ec != std::errc() || r.ptr != end) return std::nullopt;
  return v;
}

std::string over_limit(int64_t count, const char* what, int64_t limit) {
  return std::to_string(count) + " " + what + " is more than the limit of " +
         std::to_string(limit) + " (sim/setup/mesh_limits.h)";
}

}  // namespace lap::sim::mesh_text
