#include "sim/setup/yaml_fields.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace lap::sim {

int yaml_line(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

std::string describe_yaml(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Scalar:
      return quote_excerpt(n.Scalar());
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "an undefined value";
  }
}

std::string join_field(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

void YamlFields::problem(int line, const std::string& field, const std::string& message) {
  problems_.push_back({file_, line, field, message});
}

void YamlFields::problem(const YAML::Node& at, const std::string& field,
                         const std::string& message) {
  problem(yaml_line(at), field, message);
}

std::optional<YAML::Node> YamlFields::load(std::string_view text) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::ParserException& e) {
    problem(e.mark.line >= 0 ? e.mark.line + 1 : 0, "(syntax)", "not valid YAML: " + e.msg);
    return std::nullopt;
  }
}

bool YamlFields::expect_map(const YAML::Node& n, const std::string& field,
                            const std::vector<std::string>& allowed) {
  if (!n.IsMap()) {
    problem(n, field, "expected a mapping, got " + describe_yaml(n));
    return false;
  }
  std::set<std::string> seen;
  for (const auto& kv : n) {
    const std::string& key = kv.first.Scalar();
    // The key as a field's name in a message: a mutated file can make one of a megabyte.
    const std::string shown = key.size() <= 60 ? key : quote_excerpt(key);
    if (!seen.insert(key).second) {
      problem(kv.first, join_field(field, shown), "field given twice (expected each field once)");
    }
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      problem(kv.first, join_field(field, shown), "unknown field (expected one of: " + list + ")");
    }
  }
  return true;
}

bool YamlFields::expect_list(const YAML::Node& n, const std::string& field, const std::string& what,
                             size_t size) {
  if (!n.IsSequence() || (size > 0 && n.size() != size)) {
    problem(n, field, "expected " + what + ", got " + describe_yaml(n));
    return false;
  }
  return true;
}

bool YamlFields::require(const YAML::Node& parent, const std::string& key,
                         const std::string& field) {
  if (!parent[key]) {
    problem(parent, join_field(field, key), "required field is missing");
    return false;
  }
  return true;
}

std::optional<std::string> YamlFields::string(const YAML::Node& n, const std::string& field) {
  if (!n.IsScalar() || n.Scalar().empty()) {
    problem(n, field, "expected a non-empty string, got " + describe_yaml(n));
    return std::nullopt;
  }
  return n.Scalar();
}

std::optional<std::string> YamlFields::word(const YAML::Node& n, const std::string& field,
                                            const std::vector<std::string_view>& choices) {
  std::optional<std::string> v = string(n, field);
  if (!v) return std::nullopt;
  if (std::find(choices.begin(), choices.end(), *v) != choices.end()) return v;
  std::string names;
  for (size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) names += i + 1 == choices.size() ? " or " : ", ";
    names += choices[i];
  }
  problem(n, field, "expected " + names + ", got " + quote_excerpt(*v));
  return std::nullopt;
}

std::optional<double> YamlFields::number(const YAML::Node& n, const std::string& field, double lo,
                                         double hi, const std::string& range_text) {
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
    problem(n, field, "expected a number " + range_text + ", got " + describe_yaml(n));
    return std::nullopt;
  }
  if (v < lo || v > hi) {
    // The text as written, not v re-printed, so the user recognises it.
    std::ostringstream s;
    s << "expected a number " << range_text << ", got "
      << (n.Scalar().size() <= 60 ? n.Scalar() : quote_excerpt(n.Scalar()));
    problem(n, field, s.str());
    return std::nullopt;
  }
  return v;
}

std::optional<double> YamlFields::positive(const YAML::Node& n, const std::string& field) {
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v) || !(v > 0.0)) {
    problem(n, field, "expected a positive number, got " + describe_yaml(n));
    return std::nullopt;
  }
  return v;
}

std::optional<int> YamlFields::integer(const YAML::Node& n, const std::string& field, int lo,
                                       int hi) {
  int v = 0;
  const std::string range = "from " + std::to_string(lo) + " to " + std::to_string(hi);
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, v) || v < lo || v > hi) {
    problem(n, field, "expected a whole number " + range + ", got " + describe_yaml(n));
    return std::nullopt;
  }
  return v;
}

std::optional<bool> YamlFields::boolean(const YAML::Node& n, const std::string& field) {
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
    problem(n, field, "expected true or false, got " + describe_yaml(n));
    return std::nullopt;
  }
  return v;
}

std::optional<Eigen::Vector3d> YamlFields::vec3(const YAML::Node& n, const std::string& field) {
  if (!expect_list(n, field, "a list of 3 numbers [x, y, z]", 3)) return std::nullopt;
  Eigen::Vector3d v;
  for (size_t i = 0; i < 3; ++i) {
    const int k = static_cast<int>(i);
    if (!n[i].IsScalar() || !YAML::convert<double>::decode(n[i], v[k]) || !std::isfinite(v[k])) {
      problem(n, field,
              "expected a list of 3 numbers [x, y, z], got " + describe_yaml(n[i]) +
                  " at position " + std::to_string(i + 1));
      return std::nullopt;
    }
  }
  return v;
}

std::optional<Eigen::Vector3d> YamlFields::direction(const YAML::Node& n,
                                                     const std::string& field) {
  const std::optional<Eigen::Vector3d> v = vec3(n, field);
  if (!v) return std::nullopt;
  if (v->norm() < 1e-9) {
    problem(n, field, "expected a non-zero direction");
    return std::nullopt;
  }
  return v->normalized();
}

}  // namespace lap::sim
