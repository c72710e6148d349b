#pragma once
/// \file
/// The files and directories a scenario refers to: resolved against the scenario's folder and
/// kept inside the trees it may read (its own folder, its allowed_paths and the caller's).
/// Internal to lap_sim.

#include <filesystem>
#include <optional>
#include <vector>

#include "sim/setup/scenario_loader.h"
#include "sim/setup/yaml_fields.h"

namespace lap::sim {

/// Resolves and checks a scenario's file references, reporting problems to `fields`.
class ScenarioFiles {
 public:
  /// `scenario_roots` is the scenario's own allowed_paths list: read_allowed_paths() fills it
  /// and file() consults it.
  ScenarioFiles(YamlFields& fields, const std::filesystem::path& scenario_file,
                const ScenarioLoadSettings& settings,
                std::vector<std::filesystem::path>& scenario_roots);

  /// Reads the allowed_paths list: each an existing directory (when files are checked).
  void read_allowed_paths(const YAML::Node& list);
  /// A file reference, resolved; nullopt when it leaves the allowed trees or does not exist.
  std::optional<std::filesystem::path> file(const YAML::Node& n, const std::string& field);

 private:
  /// `text` made absolute and canonical; nullopt, and a problem at `n`, when it cannot be (a
  /// name too long, a loop of symbolic links: the file system's own refusal, never a throw).
  [[nodiscard]] std::optional<std::filesystem::path> resolve(const YAML::Node& n,
                                                             const std::string& field,
                                                             const std::string& text) const;
  [[nodiscard]] bool inside_allowed(const std::filesystem::path& resolved) const;

  YamlFields& fields_;
  const ScenarioLoadSettings& settings_;
  std::filesystem::path dir_;  ///< the scenario's folder, absolute
  std::vector<std::filesystem::path>& scenario_roots_;
};

}  // namespace lap::sim
