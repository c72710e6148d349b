#include "sim/authoring/expert_benchmarks.h"

#include <cmath>
#include <cstdio>
#include <random>

#include "hardware/scripted_device.h"
#include "sim/authoring/expert_run.h"
#include "sim/runtime/session.h"

namespace lap::sim {

namespace {

/// A uniform number in [lo, hi] from the generator's bits (the same on every standard library).
double uniform(std::mt19937& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 8) / static_cast<double>(1U << 24));
}

/// The planner's expert settings for the scenario (expert_run_settings), varied: the slant ±2°, the
/// grasp ±2 mm along the catheter and ±0.05 along the jaws, the start ±1 mm (of the order a
/// surgeon's placement varies by; estimates).
ExpertRunSettings varied(ExpertRunSettings s, std::mt19937& rng) {
  s.entry_slant_deg = uniform(rng, s.entry_slant_deg - 2.0, s.entry_slant_deg + 2.0);
  s.grasp_from_tip_m = uniform(rng, s.grasp_from_tip_m - 0.002, s.grasp_from_tip_m + 0.002);
  s.grasp_depth = uniform(rng, s.grasp_depth - 0.05, s.grasp_depth + 0.05);
  s.start_out_m = uniform(rng, s.start_out_m - 0.001, s.start_out_m + 0.001);
  return s;
}

std::string describe(const ExpertRunSettings& s) {
  char text[160];
  std::snprintf(text, sizeof(text),
                "slant %.2f deg, grasp %.1f mm from the tip at %.2f, start %.1f mm",
                s.entry_slant_deg, s.grasp_from_tip_m * 1e3, s.grasp_depth, s.start_out_m * 1e3);
  return text;
}

/// One varied run: its metrics, or why it did not succeed.
Result<std::vector<Metric>> run_variant(const Scene& scene, const SessionModel& model,
                                        const ExpertRunSettings& s) {
  const Result<ExpertRun> plan = plan_expert_run(scene, model, s);
  if (!plan.ok()) return plan.diagnostics();
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices{
      std::make_unique<hardware::ScriptedDevice>(plan.value().left, "left"),
      std::make_unique<hardware::ScriptedDevice>(plan.value().right, "right")};
  RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = plan.value().right.duration_s() + 1.0;
  auto session = Session::create(scene, std::move(devices), rs);
  if (!session.ok()) return session.diagnostics();
  const SessionMetrics m = session.value()->run();
  if (m.task.result != TaskResult::kSuccess) {
    std::string why = std::string(to_string(m.task.result));
    for (size_t i = 0; i < m.task.reason_count; ++i) {
      why += std::string(i == 0 ? ": " : ", ") + std::string(to_string(m.task.reasons[i]));
    }
    return diagnostic(why);
  }
  return m.training;
}

}  // namespace

Result<ExpertBenchmarks> plan_expert_benchmarks(const Scene& scene,
                                                const ExpertBenchmarkSettings& settings) {
  RuntimeSettings rs;
  rs.fast = true;
  const auto model = SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
  if (!model.ok()) return model.diagnostics();
  ExpertBenchmarks out;
  std::mt19937 rng(settings.seed);
  std::vector<std::vector<double>> values(settings.metrics.size());
  for (int run = 0; run < settings.runs; ++run) {
    const ExpertRunSettings base = expert_run_settings(scene.scenario);
    const ExpertRunSettings s = run == 0 ? base : varied(base, rng);
    ++out.runs;
    const Result<std::vector<Metric>> metrics = run_variant(scene, *model.value(), s);
    if (!metrics.ok()) {
      out.failures.push_back(describe(s) + ": " + metrics.message());
      continue;
    }
    ++out.succeeded;
    for (size_t k = 0; k < settings.metrics.size(); ++k) {
      for (const Metric& m : metrics.value()) {
        if (m.name == settings.metrics[k].first && std::isfinite(m.value)) {
          values[k].push_back(m.value);
        }
      }
    }
  }
  if (out.succeeded < 2) {
    std::string why = "fewer than two of the " + std::to_string(out.runs) + " expert runs succeed";
    for (const std::string& f : out.failures) why += "; " + f;
    return diagnostic(why);
  }
  for (size_t k = 0; k < settings.metrics.size(); ++k) {
    const std::vector<double>& v = values[k];
    const std::string& name = settings.metrics[k].first;
    if (v.size() < 2) {
      out.left_out.push_back(name + " (undefined in the runs)");
      continue;
    }
    double mean = 0.0;
    for (const double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    double ss = 0.0;
    for (const double x : v) ss += (x - mean) * (x - mean);
    const double sd = std::sqrt(ss / static_cast<double>(v.size() - 1));  // the sample's SD
    if (mean != 0.0 && sd <= 1e-9 * std::abs(mean)) {
      out.left_out.push_back(name + " (the same in every run: no spread)");
      continue;
    }
    out.spec.metrics.push_back({name, mean, sd, settings.metrics[k].second, 0});
  }
  out.spec.source = "the planner's expert run and " + std::to_string(out.runs - 1) +
                    " variants of its approach (laptrainer-cli expert-benchmarks --runs " +
                    std::to_string(out.runs) + "; " + std::to_string(out.succeeded) +
                    " succeeded): planned, not measured on surgeons";
  return out;
}

std::string proficiency_yaml(const ProficiencySpec& spec) {
  std::string out = "proficiency:\n  source: \"";
  for (const char c : spec.source) {
    if (c == '"' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  out += "\"\n  metrics:\n";
  for (const MetricBenchmark& b : spec.metrics) {
    char line[256];
    std::snprintf(line, sizeof(line), "    %s: {mean: %.6g, sd: %.3g%s}\n", b.metric.c_str(),
                  b.mean, b.sd, b.higher_is_better ? ", better: higher" : "");
    out += line;
  }
  return out;
}

}  // namespace lap::sim
