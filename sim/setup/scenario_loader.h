#pragma once
/// \file
/// Loads and checks scenario v1 files (YAML). Every problem is collected, not just the first, and
/// each names the file, the line, the field and what was expected.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

/// Choices the caller makes, not the file.
struct ScenarioLoadSettings {
  /// Directories outside the scenario's folder tree that referenced files may live in, in
  /// addition to those the scenario itself lists under allowed_paths.
  std::vector<std::filesystem::path> allowed_paths;
  /// Check that referenced files exist (off only for tests of pure syntax).
  bool check_files = true;
};

/// The scenario, or everything wrong with it (every problem found, not only the first: each
/// `file:line: field: what was expected`).
using ScenarioLoadResult = Result<Scenario>;

/// Reads and checks a scenario file.
[[nodiscard]] ScenarioLoadResult load_scenario(const std::filesystem::path& file,
                                               const ScenarioLoadSettings& settings = {});

/// Checks scenario text as if it were the file `file` (paths resolve against its folder).
[[nodiscard]] ScenarioLoadResult parse_scenario(std::string_view text,
                                                const std::filesystem::path& file,
                                                const ScenarioLoadSettings& settings = {});

/// The scenario the application opens when none is given: share/laptrainer/scenarios/default.yaml
/// beside the running binary (an installed package, wherever unpacked), else the source tree's.
[[nodiscard]] std::filesystem::path default_scenario_path();

}  // namespace lap::sim
