#include "sim/report/proficiency.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace lap::sim {

std::vector<BenchmarkResult> assess_proficiency(const ProficiencySpec& spec,
                                                const std::vector<Metric>& metrics) {
  std::vector<BenchmarkResult> out;
  for (const MetricBenchmark& b : spec.metrics) {
    BenchmarkResult r;
    r.benchmark = b;
    r.value = std::numeric_limits<double>::quiet_NaN();
    for (const Metric& m : metrics) {
      if (m.name == b.metric) r.value = m.value;
    }
    r.limit = b.higher_is_better ? b.mean - 2.0 * b.sd : b.mean + 2.0 * b.sd;
    r.met =
        std::isfinite(r.value) && (b.higher_is_better ? r.value >= r.limit : r.value <= r.limit);
    out.push_back(r);
  }
  return out;
}

nlohmann::ordered_json proficiency_to_json(const ProficiencySpec& spec,
                                           const std::vector<Metric>& metrics) {
  nlohmann::ordered_json j;
  j["source"] = spec.source;
  nlohmann::ordered_json each = nlohmann::ordered_json::object();
  int met = 0;
  const std::vector<BenchmarkResult> results = assess_proficiency(spec, metrics);
  for (const BenchmarkResult& r : results) {
    nlohmann::ordered_json x;
    x["value"] = std::isfinite(r.value) ? nlohmann::ordered_json(r.value) : nullptr;
    x["mean"] = r.benchmark.mean;
    x["sd"] = r.benchmark.sd;
    x["better"] = r.benchmark.higher_is_better ? "higher" : "lower";
    x["limit"] = r.limit;
    x["met"] = r.met;
    each[r.benchmark.metric] = x;
    met += r.met ? 1 : 0;
  }
  j["metrics"] = each;
  j["met"] = met;
  j["of"] = static_cast<int>(results.size());
  j["all_met"] = met == static_cast<int>(results.size());
  return j;
}

}  // namespace lap::sim
