#include "sim/runtime/loop_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lap::sim {

void LoopStats::add(double lateness_s, double step_s) noexcept {
  ++ticks_;
  const double late = std::max(0.0, lateness_s);
  const double bin = std::floor(late * 1e6);
  const int index = bin >= kBins || !(bin >= 0.0) ? kBins : static_cast<int>(bin);
  ++histogram_[static_cast<size_t>(index)];
  if (step_s > period_s_) ++overruns_;
  if (late > kMissedLateS) ++missed_;
  worst_step_s_ = std::max(worst_step_s_, step_s);
  worst_late_s_ = std::max(worst_late_s_, late);
  step_sum_s_ += step_s;
  const double step_bin = std::floor(step_s / kStepBinS);
  const int s =
      step_bin >= kStepBins || !(step_bin >= 0.0) ? kStepBins : static_cast<int>(step_bin);
  ++step_histogram_[static_cast<size_t>(s)];
}

double LoopStats::achieved_rate_hz() const {
  return elapsed_s_ > 0.0 ? static_cast<double>(ticks_) / elapsed_s_ : 0.0;
}

double LoopStats::mean_step_s() const {
  return ticks_ > 0 ? step_sum_s_ / static_cast<double>(ticks_) : 0.0;
}

double LoopStats::step_quantile_s(double q) const {
  if (ticks_ == 0) return 0.0;
  const auto need =
      static_cast<int64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(ticks_)));
  int64_t seen = 0;
  for (int i = 0; i <= kStepBins; ++i) {
    seen += step_histogram_[static_cast<size_t>(i)];
    if (seen >= std::max<int64_t>(need, 1)) {
      return i == kStepBins ? worst_step_s_ : static_cast<double>(i + 1) * kStepBinS;
    }
  }
  return worst_step_s_;
}

double LoopStats::jitter_quantile_s(double q) const {
  if (ticks_ == 0) return 0.0;
  const auto need =
      static_cast<int64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(ticks_)));
  int64_t seen = 0;
  for (int i = 0; i <= kBins; ++i) {
    seen += histogram_[static_cast<size_t>(i)];
    if (seen >= std::max<int64_t>(need, 1)) {
      return i == kBins ? worst_late_s_ : static_cast<double>(i + 1) * 1e-6;
    }
  }
  return worst_late_s_;
}

}  // namespace lap::sim
