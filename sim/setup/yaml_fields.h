#pragma once
/// \file
/// Schema-free reading of YAML fields: mappings with known keys, required fields, strings,
/// choices, numbers in ranges, booleans and vectors. Each problem becomes a Diagnostic
/// (`file:line: field: message`) and reading goes on, so one pass reports everything wrong with
/// a file. Internal to lap_sim, which alone links yaml-cpp.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/diagnostic.h"

namespace lap::sim {

/// The 1-based line a node starts on, or 0 when it has none.
[[nodiscard]] int yaml_line(const YAML::Node& n);

/// A node as messages show it: 'text', a list, a mapping or nothing.
[[nodiscard]] std::string describe_yaml(const YAML::Node& n);

/// The field path `parent.key`, or `key` at the top of the document.
[[nodiscard]] std::string join_field(const std::string& parent, const std::string& key);

/// Reads typed values from the YAML of one file and collects a Diagnostic for each problem
/// instead of stopping at the first. A reader returns nullopt (or false) when it has reported.
class YamlFields {
 public:
  /// Problems will name `file`.
  explicit YamlFields(std::string file) : file_(std::move(file)) {}

  /// Records a problem at a line (0: none applies).
  void problem(int line, const std::string& field, const std::string& message);
  /// Records a problem at the line where `at` starts.
  void problem(const YAML::Node& at, const std::string& field, const std::string& message);
  /// Hands over the problems recorded so far.
  [[nodiscard]] std::vector<Diagnostic> take_problems() { return std::move(problems_); }

  /// Parses YAML text; a syntax error is recorded as a `(syntax)` problem and gives nullopt.
  [[nodiscard]] std::optional<YAML::Node> load(std::string_view text);

  /// Checks n is a mapping and reports repeated keys and keys not in `allowed`.
  bool expect_map(const YAML::Node& n, const std::string& field,
                  const std::vector<std::string>& allowed);
  /// Checks n is a list (of exactly `size` items when size > 0); `what` is what was expected.
  bool expect_list(const YAML::Node& n, const std::string& field, const std::string& what,
                   size_t size = 0);
  /// Checks parent has `key`; `field` is the parent's path.
  bool require(const YAML::Node& parent, const std::string& key, const std::string& field);

  /// A non-empty string.
  std::optional<std::string> string(const YAML::Node& n, const std::string& field);
  /// One of `choices`; otherwise the message lists them ("expected a, b or c, got 'x'").
  std::optional<std::string> word(const YAML::Node& n, const std::string& field,
                                  const std::vector<std::string_view>& choices);
  /// The value of one of an enumeration's spellings, reported as word() does.
  template <typename E>
  std::optional<E> one_of(const YAML::Node& n, const std::string& field,
                          std::initializer_list<std::pair<const char*, E>> choices);

  /// A finite number from lo to hi; `range_text` tells the user which (e.g. "from 0 to 1 (m)").
  std::optional<double> number(const YAML::Node& n, const std::string& field, double lo, double hi,
                               const std::string& range_text);
  /// A finite number above zero.
  std::optional<double> positive(const YAML::Node& n, const std::string& field);
  /// A whole number from lo to hi.
  std::optional<int> integer(const YAML::Node& n, const std::string& field, int lo, int hi);
  /// true or false.
  std::optional<bool> boolean(const YAML::Node& n, const std::string& field);
  /// A list of 3 finite numbers.
  std::optional<Eigen::Vector3d> vec3(const YAML::Node& n, const std::string& field);
  /// A non-zero vec3, normalized.
  std::optional<Eigen::Vector3d> direction(const YAML::Node& n, const std::string& field);

  /// Reads parent[key] as number() into target when the key is given; `field` is the parent's.
  template <typename T>
  void optional_number(const YAML::Node& parent, const std::string& key, const std::string& field,
                       T& target, double lo, double hi, const std::string& range_text) {
    if (parent[key]) {
      if (auto v = number(parent[key], join_field(field, key), lo, hi, range_text)) target = *v;
    }
  }

 private:
  std::string file_;
  std::vector<Diagnostic> problems_;
};

template <typename E>
std::optional<E> YamlFields::one_of(const YAML::Node& n, const std::string& field,
                                    std::initializer_list<std::pair<const char*, E>> choices) {
  std::vector<std::string_view> names;
  for (const auto& choice : choices) names.emplace_back(choice.first);
  const std::optional<std::string> v = word(n, field, names);
  if (!v) return std::nullopt;
  for (const auto& [name, value] : choices) {
    if (*v == name) return value;
  }
  return std::nullopt;
}

}  // namespace lap::sim
