#pragma once
/// \file
/// Expert benchmarks for a scenario's training metrics (its `proficiency:` section,
/// docs/metrics.md) from the planner's expert runs: the expert's insertion (expert_run.h)
/// planned again with its approach varied — the catheter's slant at entry, where the jaws take
/// it, how far along them, where the tip starts — each run in a --fast session, and the mean and
/// standard deviation of each metric over the runs that succeed. A stand-in for a cohort of
/// human experts until one is measured: it says how the simulator scores competent variants of
/// the procedure, not how surgeons perform it, and the scenario's `source` must say so.

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "sim/setup/scenario.h"
#include "sim/setup/scene.h"

namespace lap::sim {

struct ExpertBenchmarkSettings {
  int runs = 12;
  uint32_t seed = 2026;
  /// The metrics benchmarked, each with the side that is better. Not the path lengths and the
  /// economy of motion: the planner moves along straight lines, so its spread (about 1 mm of
  /// 250 mm) would set a bar no hand meets; they wait for measured experts.
  std::vector<std::pair<std::string, bool>> metrics = {
      {"completion_time_s", false},     {"max_force_duct_n", false},   {"mean_force_duct_n", false},
      {"time_over_threshold_s", false}, {"max_squeeze_duct_n", false}, {"catheter_drops", false},
      {"max_insertion_depth_m", true}};
};

struct ExpertBenchmarks {
  ProficiencySpec spec;  ///< its source says how it was made
  int runs = 0;
  int succeeded = 0;
  std::vector<std::string> failures;  ///< per run that did not succeed: its settings and result
  /// Metrics left out: undefined in the runs, or the same in every run though not zero (the
  /// variation does not reach them: no spread to benchmark).
  std::vector<std::string> left_out;
};

/// Plans and runs `settings.runs` varied expert runs on the scene. Fails, saying why, when the
/// planner cannot plan for the scene or fewer than two runs succeed.
[[nodiscard]] Result<ExpertBenchmarks> plan_expert_benchmarks(
    const Scene& scene, const ExpertBenchmarkSettings& settings = {});

/// The `proficiency:` section as YAML text (two-space indents), its source quoted.
[[nodiscard]] std::string proficiency_yaml(const ProficiencySpec& spec);

}  // namespace lap::sim
