#include "sim/report/proficiency_progress.h"

#include <algorithm>

#include "sim/report/proficiency.h"

namespace lap::sim {

std::vector<ProficiencyProgress> proficiency_progress(
    const ProficiencySpec& spec, const std::vector<std::vector<Metric>>& sessions) {
  std::vector<ProficiencyProgress> out;
  out.reserve(spec.metrics.size());
  for (const MetricBenchmark& b : spec.metrics) {
    ProficiencyProgress p;
    p.benchmark = b;
    out.push_back(p);
  }
  for (const std::vector<Metric>& metrics : sessions) {
    // The single session's verdicts, as the run JSON gives them (one rule for both).
    const std::vector<BenchmarkResult> verdicts = assess_proficiency(spec, metrics);
    for (size_t k = 0; k < out.size(); ++k) {
      ProficiencyProgress& p = out[k];
      p.limit = verdicts[k].limit;
      p.values.push_back(verdicts[k].value);
      p.met.push_back(verdicts[k].met);
      const size_t n = p.met.size();
      if (p.proficient_at < 0 && n >= 2 && p.met[n - 1] && p.met[n - 2]) {
        p.proficient_at = static_cast<int>(n - 1);
      }
    }
  }
  return out;
}

int proficient_at(const std::vector<ProficiencyProgress>& progress) {
  if (progress.empty()) return -1;
  int all = 0;
  for (const ProficiencyProgress& p : progress) {
    if (p.proficient_at < 0) return -1;
    all = std::max(all, p.proficient_at);
  }
  return all;
}

}  // namespace lap::sim
