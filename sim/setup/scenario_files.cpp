#include "sim/setup/scenario_files.h"

#include <algorithm>
#include <system_error>

#include "core/bounded_file.h"
#include "sim/setup/gltf_references.h"

namespace lap::sim {
namespace fs = std::filesystem;

ScenarioFiles::ScenarioFiles(YamlFields& fields, const fs::path& scenario_file,
                             const ScenarioLoadSettings& settings,
                             std::vector<fs::path>& scenario_roots)
    : fields_(fields),
      settings_(settings),
      dir_(fs::absolute(scenario_file).parent_path()),
      scenario_roots_(scenario_roots) {}

void ScenarioFiles::read_allowed_paths(const YAML::Node& list) {
  if (!fields_.expect_list(list, "allowed_paths", "a list of directories")) return;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string f = "allowed_paths[" + std::to_string(i) + "]";
    const std::optional<std::string> text = fields_.string(list[i], f);
    if (!text) continue;
    const std::optional<fs::path> canonical = resolve(list[i], f, *text);
    if (!canonical) continue;
    const fs::path& resolved = *canonical;
    std::error_code ec;
    if (settings_.confine_allowed_paths && !inside_folder(dir_, resolved) &&
        std::none_of(settings_.confine_allowed_paths->begin(),
                     settings_.confine_allowed_paths->end(),
                     [&](const fs::path& root) { return inside_folder(root, resolved); })) {
      fields_.problem(list[i], f,
                      "directory " + quote_excerpt(*text) +
                          " is outside the scenario's folder, and this scenario may not open "
                          "others (it came with a recording: allow a folder with --allow-path)");
    } else if (settings_.check_files && !fs::is_directory(resolved, ec)) {
      fields_.problem(list[i], f,
                      "directory " + quote_excerpt(*text) + " not found (looked for " +
                          resolved.string() + ")");
    } else {
      scenario_roots_.push_back(resolved);
    }
  }
}

std::optional<fs::path> ScenarioFiles::file(const YAML::Node& n, const std::string& field) {
  const std::optional<std::string> text = fields_.string(n, field);
  if (!text) return std::nullopt;
  const std::optional<fs::path> canonical = resolve(n, field, *text);
  if (!canonical) return std::nullopt;
  const fs::path& resolved = *canonical;
  if (!inside_allowed(resolved)) {
    fields_.problem(n, field,
                    "path " + quote_excerpt(*text) +
                        " leaves the scenario's folder (expected a file under " + dir_.string() +
                        " or under a directory listed in allowed_paths)");
    return std::nullopt;
  }
  if (settings_.check_files) {
    std::error_code ec;
    const fs::file_type type = fs::status(resolved, ec).type();
    if (type == fs::file_type::not_found || (ec && type == fs::file_type::none)) {
      fields_.problem(
          n, field,
          "file " + quote_excerpt(*text) + " not found (looked for " + resolved.string() + ")");
      return std::nullopt;
    }
    if (type != fs::file_type::regular) {
      // A FIFO would block its reader, /dev/zero never end (core/bounded_file.h).
      fields_.problem(n, field,
                      quote_excerpt(*text) + " is " + describe_file_type(type) +
                          "; expected a regular file (looked at " + resolved.string() + ")");
      return std::nullopt;
    }
  }
  return resolved;
}

std::optional<fs::path> ScenarioFiles::resolve(const YAML::Node& n, const std::string& field,
                                               const std::string& text) const {
  // The error_code overload: a component longer than NAME_MAX threw (ENAMETOOLONG) through the
  // loader (found by fuzz_scenario; tests/fuzz/regressions/scenario).
  const fs::path p(text);
  // A scenario names its files and folders relative to its own folder (issue 25: no absolute
  // paths). Its reach beyond that folder is then only what it declares, visibly, in its own
  // allowed_paths (relative too) and what the person running it allows (--allow-path); a
  // scenario that came with a recording may not declare any (confine_allowed_paths).
  if (p.is_absolute()) {
    fields_.problem(n, field,
                    "path " + quote_excerpt(text) +
                        " is absolute (expected a path relative to the scenario's folder, " +
                        dir_.string() +
                        "; a file elsewhere is named by a relative path, its folder listed in "
                        "allowed_paths or passed with --allow-path)");
    return std::nullopt;
  }
  std::error_code ec;
  fs::path resolved = fs::weakly_canonical(dir_ / p, ec);
  if (ec) {
    fields_.problem(n, field,
                    "path " + quote_excerpt(text) + " cannot be resolved (" + ec.message() + ")");
    return std::nullopt;
  }
  return resolved;
}

bool ScenarioFiles::inside_allowed(const fs::path& resolved) const {
  // Compared element by element after canonicalising, so `..` and symlinks cannot escape.
  auto under = [&resolved](const fs::path& root) {
    std::error_code ec;
    const fs::path r = fs::weakly_canonical(root, ec);
    if (ec) return false;
    auto rit = r.begin();
    auto pit = resolved.begin();
    for (; rit != r.end(); ++rit, ++pit) {
      if (rit->empty()) continue;  // trailing separator
      if (pit == resolved.end() || *rit != *pit) return false;
    }
    return true;
  };
  if (under(dir_)) return true;
  for (const auto& a : scenario_roots_) {
    if (under(a)) return true;
  }
  for (const auto& a : settings_.allowed_paths) {
    if (under(a)) return true;
  }
  return false;
}

}  // namespace lap::sim
