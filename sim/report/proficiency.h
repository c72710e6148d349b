#pragma once
/// \file
/// A session's training metrics against the scenario's expert benchmarks (the scenario's
/// `proficiency:`; docs/metrics.md): each benchmarked metric met or not, where met means within
/// two standard deviations of the experts' mean on the side that counts — the
/// proficiency-based progression of Gallagher et al. (Ann Surg 2005;241:364-372), whose
/// proficiency levels are the experts' performance. A metric that is undefined in the session
/// (null) is not met.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "sim/runtime/training_metrics.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

struct BenchmarkResult {
  MetricBenchmark benchmark;
  double value = 0.0;  ///< the session's (NaN: undefined)
  double limit = 0.0;  ///< mean + 2 SD (lower is better) or mean − 2 SD (higher is)
  bool met = false;
};

/// Each benchmark of `spec` against `metrics`, in the scenario's order.
[[nodiscard]] std::vector<BenchmarkResult> assess_proficiency(const ProficiencySpec& spec,
                                                              const std::vector<Metric>& metrics);

/// The JSON's "proficiency" object: source, per metric {value, mean, sd, better, limit, met},
/// met (how many), of (how many benchmarks), all_met.
[[nodiscard]] nlohmann::ordered_json proficiency_to_json(const ProficiencySpec& spec,
                                                         const std::vector<Metric>& metrics);

}  // namespace lap::sim
