#pragma once
/// \file
/// A trainee's progress toward proficiency over their sessions of one scenario (issue 24: expert
/// mean ± 2 SD; proficient when met in two consecutive sessions — the proficiency-based
/// progression of Gallagher et al., Ann Surg 2005;241:364-372, where a trainee moves on after
/// reaching the experts' level on two consecutive trials). Per benchmarked metric: where each
/// session stood against the limit, and the session that made the trainee proficient.

#include <string>
#include <vector>

#include "sim/runtime/training_metrics.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

struct ProficiencyProgress {
  MetricBenchmark benchmark;
  double limit = 0.0;          ///< mean + 2 SD (lower is better) or mean − 2 SD (higher is)
  std::vector<double> values;  ///< per session, oldest first (NaN: undefined there)
  std::vector<bool> met;       ///< per session
  /// The session (0-based, oldest first) whose benchmark was met for the second time in a row:
  /// proficient from there on; -1 while not.
  int proficient_at = -1;
};

/// Each benchmark of `spec` over `sessions` (each session's metrics, oldest first).
[[nodiscard]] std::vector<ProficiencyProgress> proficiency_progress(
    const ProficiencySpec& spec, const std::vector<std::vector<Metric>>& sessions);

/// Proficient in the whole scenario: every benchmark proficient; the session from which all are
/// (the latest of their proficient_at), or -1.
[[nodiscard]] int proficient_at(const std::vector<ProficiencyProgress>& progress);

}  // namespace lap::sim
