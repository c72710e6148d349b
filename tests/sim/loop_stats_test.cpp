// A loop's statistics (sim/runtime/loop_stats.h): the quantiles read back from its histograms
// are the bins' upper edges of what was put in, counted by brute force.

#include "sim/runtime/loop_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace lap::sim {
namespace {

// The quantile q of `steps` as the histogram states it: the upper edge of the bin holding the
// ceil(q n)-th smallest.
double brute_force_quantile(std::vector<double> steps, double q) {
  std::sort(steps.begin(), steps.end());
  const auto k = static_cast<size_t>(std::ceil(q * static_cast<double>(steps.size())));
  const double v = steps[std::max<size_t>(k, 1) - 1];
  return (std::floor(v / LoopStats::kStepBinS) + 1.0) * LoopStats::kStepBinS;
}

TEST(LoopStats, StepQuantilesAreTheBinsOfTheSortedSteps) {
  std::mt19937 rng(7);
  std::lognormal_distribution<double> step(std::log(8e-6), 0.4);  // around 8 µs
  LoopStats stats;
  std::vector<double> steps;
  for (int i = 0; i < 20000; ++i) {
    const double s = step(rng);
    steps.push_back(s);
    stats.add(0.0, s);
  }
  for (const double q : {0.5, 0.9, 0.99, 0.999}) {
    EXPECT_DOUBLE_EQ(stats.step_quantile_s(q), brute_force_quantile(steps, q)) << q;
  }
}

TEST(LoopStats, AStepBeyondTheHistogramIsTheWorst) {
  LoopStats stats;
  for (int i = 0; i < 999; ++i) stats.add(0.0, 10.1e-6);
  stats.add(0.0, 3e-3);  // beyond 1 ms
  EXPECT_DOUBLE_EQ(stats.step_quantile_s(0.5), 10.25e-6);
  EXPECT_DOUBLE_EQ(stats.step_quantile_s(0.999), 10.25e-6);
  EXPECT_DOUBLE_EQ(stats.step_quantile_s(1.0), 3e-3);
  EXPECT_DOUBLE_EQ(stats.worst_step_s(), 3e-3);
  EXPECT_EQ(LoopStats().step_quantile_s(0.5), 0.0);
}

}  // namespace
}  // namespace lap::sim
