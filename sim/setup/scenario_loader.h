#pragma once
/// \file
/// Loads and checks scenario v1 files (YAML). Every problem is collected, not just the first, and
/// each names the file, the line, the field and what was expected.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

/// A scenario is a few kilobytes of YAML (the default patient's is 19 kB, with its comments and
/// benchmarks): a file over 4 MiB is not one, and is refused unread (as /dev/zero, a FIFO or a
/// folder are).
inline constexpr std::uintmax_t kMaxScenarioFileBytes = std::uintmax_t{4} << 20;

/// Choices the caller makes, not the file.
struct ScenarioLoadSettings {
  /// Directories outside the scenario's folder tree that referenced files may live in, in
  /// addition to those the scenario itself lists under allowed_paths.
  std::vector<std::filesystem::path> allowed_paths;
  /// Check that referenced files exist (off only for tests of pure syntax).
  bool check_files = true;
  /// When set, the scenario's own allowed_paths may only name folders inside its folder or
  /// these: a scenario that came with a recording for review is untrusted, and its
  /// `allowed_paths: ["/"]` would open every folder to its meshes.
  std::optional<std::vector<std::filesystem::path>> confine_allowed_paths;
};

/// The scenario, or everything wrong with it (every problem found, not only the first: each
/// `file:line: field: what was expected`).
using ScenarioLoadResult = Result<Scenario>;

/// Reads and checks a scenario file: a regular file of at most kMaxScenarioFileBytes.
[[nodiscard]] ScenarioLoadResult load_scenario(const std::filesystem::path& file,
                                               const ScenarioLoadSettings& settings = {});

/// Checks scenario text as if it were the file `file` (paths resolve against its folder).
[[nodiscard]] ScenarioLoadResult parse_scenario(std::string_view text,
                                                const std::filesystem::path& file,
                                                const ScenarioLoadSettings& settings = {});

/// Where the shipped scenarios are, in the order looked at: share/laptrainer/scenarios beside the
/// running binary (an installed package, wherever unpacked), the source tree's scenarios/, then
/// /usr/share and /usr/local/share's (whether or not they exist).
[[nodiscard]] std::vector<std::filesystem::path> shipped_scenario_folders();

/// The scenario the application opens when none is given: default.yaml in the first of
/// shipped_scenario_folders() that has one, else the source tree's.
[[nodiscard]] std::filesystem::path default_scenario_path();

}  // namespace lap::sim
