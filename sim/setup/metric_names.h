#pragma once
/// \file
/// The training metrics' names (docs/metrics.md), for checking a scenario's proficiency
/// benchmarks when it is loaded: the fixed names, and the per-organ ones built from an organ's
/// name in snake_case (the task's target is "duct"). The metrics themselves are computed by
/// sim/runtime/training_metrics.h, whose test checks that every name it writes is known here.

#include <string>
#include <vector>

namespace lap::sim {

/// `name` lower-cased with every run of other characters than [a-z0-9] one '_'
/// ("Common Bile-Duct" → "common_bile_duct").
[[nodiscard]] std::string snake_case(const std::string& name);

/// The metrics that do not depend on the scene's organs, in the report's order.
[[nodiscard]] const std::vector<std::string>& fixed_metric_names();

/// The per-organ metrics' names for an organ called `organ` in them ("duct", "gallbladder"):
/// max_force_<organ>_n, mean_force_<organ>_n, contact_time_<organ>_s,
/// time_over_threshold_<organ>_s.
[[nodiscard]] std::vector<std::string> organ_metric_names(const std::string& organ);

/// A metric `name` is reported for a scene with organs `organ_names` (scenario names).
[[nodiscard]] bool is_metric_name(const std::string& name,
                                  const std::vector<std::string>& organ_names);

}  // namespace lap::sim
