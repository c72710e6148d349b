#pragma once
/// \file
/// The patients a trainee can choose from: every scenario file in the scenarios folder the
/// application uses (the installed package's share/laptrainer/scenarios beside the binary, else
/// the source tree's: sim::default_scenario_path), each with its name, description, difficulty,
/// task and preview picture (previews/<stem>.png in the same folder, rendered by
/// `laptrainer --screenshot` through app/make-previews.sh). A file that does not load is listed
/// with its problems, so that a broken scenario is seen, not silently missing.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sim/setup/scenario.h"

namespace lap::app {

struct CatalogEntry {
  std::filesystem::path file;  ///< the scenario file
  std::string stem;            ///< its name without .yaml ("patient_easy")
  std::string name;            ///< the scenario's `name` (the file's stem when it did not load)
  std::string description;
  std::string difficulty;  ///< introductory, easy, moderate, hard or "" (not graded)
  std::optional<sim::TaskSpec> task;
  std::filesystem::path preview;  ///< previews/<stem>.png; empty when there is none
  std::string problems;           ///< why it did not load; empty when it did
};

/// 0 introductory, 1 easy, 2 moderate, 3 hard, 4 not graded: the chooser's order.
[[nodiscard]] int difficulty_rank(const std::string& difficulty);

/// The scenario files (*.yaml, *.yml) in `folder`, loaded, ordered by difficulty then name.
[[nodiscard]] std::vector<CatalogEntry> scan_scenarios(const std::filesystem::path& folder);

/// One scenario file as an entry (its preview looked for beside it, under previews/).
[[nodiscard]] CatalogEntry catalog_entry(const std::filesystem::path& file);

/// The folder the application's scenarios are in: that of sim::default_scenario_path().
[[nodiscard]] std::filesystem::path scenarios_folder();

/// The task in words for the briefing (what to do, and what ends it in failure), one sentence
/// a line, from the scenario's thresholds.
[[nodiscard]] std::vector<std::string> task_in_words(const sim::TaskSpec& task);

}  // namespace lap::app
