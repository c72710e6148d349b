#include "sim/runtime/loop_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lap::sim {
namespace {

// The value at quantile q of `ticks` samples binned in `histogram` (bins of bin_s, the last one
// overflow): the upper edge of the bin holding the ceil(q n)-th smallest, `overflow` beyond.
template <size_t N>
double histogram_quantile(const std::array<int64_t, N>& histogram, int64_t ticks, double q,
                          double bin_s, double overflow) {
  if (ticks == 0) return 0.0;
  const auto need =
      static_cast<int64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(ticks)));
  int64_t seen = 0;
  for (size_t i = 0; i < N; ++i) {
    seen += histogram[i];
    if (seen >= std::max<int64_t>(need, 1)) {
      return i + 1 == N ? overflow : static_cast<double>(i + 1) * bin_s;
    }
  }
  return overflow;
}

}  // namespace

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
  return histogram_quantile(step_histogram_, ticks_, q, kStepBinS, worst_step_s_);
}

double LoopStats::jitter_quantile_s(double q) const {
  return histogram_quantile(histogram_, ticks_, q, 1e-6, worst_late_s_);
}

}  // namespace lap::sim
