#pragma once
/// \file
/// Statistics one loop keeps about itself (docs/architecture.md, "The three loops"): ticks,
/// achieved rate, period jitter as a histogram (1 µs bins up to 5 ms, one overflow bin), overruns
/// (a step longer than the period), deadlines missed (a tick starting more than 2 ms late), the
/// worst step and the worst lateness, and the steps' durations as a histogram (0.25 µs bins up to
/// 1 ms, one overflow bin: the haptic step's median and p99.9 for the benchmarks). add() is
/// real-time safe: the histograms are sized at construction.

#include <array>
#include <cstdint>
#include <string>

namespace lap::sim {

class LoopStats {
 public:
  static constexpr int kBins = 5000;            ///< 1 µs each
  static constexpr double kMissedLateS = 2e-3;  ///< a tick later than this missed its deadline
  static constexpr int kStepBins = 4000;        ///< kStepBinS each
  static constexpr double kStepBinS = 0.25e-6;

  explicit LoopStats(double period_s = 0.001) : period_s_(period_s) {}

  /// One tick: how late it started against its schedule and how long its step took [s].
  void add(double lateness_s, double step_s) noexcept;
  /// The wall time the loop has run [s] (for the achieved rate).
  void set_elapsed(double elapsed_s) noexcept { elapsed_s_ = elapsed_s; }

  [[nodiscard]] int64_t ticks() const { return ticks_; }
  [[nodiscard]] double period_s() const { return period_s_; }
  /// The wall time the loop ran [s], as set_elapsed() last gave it.
  [[nodiscard]] double elapsed_s() const { return elapsed_s_; }
  [[nodiscard]] double achieved_rate_hz() const;
  /// Lateness (start jitter) at quantile q in [0, 1], from the histogram (bin upper edge) [s].
  [[nodiscard]] double jitter_quantile_s(double q) const;
  [[nodiscard]] int64_t overruns() const { return overruns_; }
  [[nodiscard]] int64_t missed_deadlines() const { return missed_; }
  [[nodiscard]] double worst_step_s() const { return worst_step_s_; }
  [[nodiscard]] double worst_lateness_s() const { return worst_late_s_; }
  [[nodiscard]] double mean_step_s() const;
  /// Step duration at quantile q in [0, 1], from its histogram (bin upper edge; beyond 1 ms the
  /// worst step) [s].
  [[nodiscard]] double step_quantile_s(double q) const;

 private:
  double period_s_;
  double elapsed_s_ = 0.0;
  int64_t ticks_ = 0;
  int64_t overruns_ = 0;
  int64_t missed_ = 0;
  double worst_step_s_ = 0.0;
  double worst_late_s_ = 0.0;
  double step_sum_s_ = 0.0;
  std::array<int64_t, kBins + 1> histogram_{};
  std::array<int64_t, kStepBins + 1> step_histogram_{};
};

}  // namespace lap::sim
