#pragma once
/// \file
/// A session's plots for the instructor's review (Qt Charts), over the session's time: the
/// force and the jaws' squeeze on the duct with the injury threshold, both tools' speeds, the
/// catheter's insertion depth with its target, the task's events marked on each time line, and
/// a cursor at the replay's time (moved in step with the 3D replay, set_cursor). The series are
/// the replay's (sim::MetricsSeries), thinned for drawing to at most kMaxPoints per series
/// keeping each bucket's extremes, so a force peak is never drawn away.

#include <QWidget>
#include <array>
#include <vector>

#include "sim/runtime/session.h"

class QChart;
class QChartView;
class QLineSeries;
class QScatterSeries;
class QValueAxis;

namespace lap::app {

/// Thins (t, v) to at most `max_points` points: each bucket's first, smallest and largest
/// values in time order, so the drawn curve keeps every peak.
[[nodiscard]] std::vector<std::pair<double, double>> thin_series(const std::vector<double>& t_s,
                                                                 const std::vector<double>& v,
                                                                 double scale, size_t max_points);

class SessionCharts : public QWidget {
  Q_OBJECT

 public:
  static constexpr size_t kMaxPoints = 3000;
  explicit SessionCharts(QWidget* parent = nullptr);

  /// Shows a session's series and events; `duct_injury_force_n` and `insertion_depth_m` draw
  /// the threshold and the target (0: none).
  void set_session(const sim::MetricsSeries& series, const sim::TaskState& task,
                   double duct_injury_force_n, double insertion_depth_m);
  /// Nothing to show (and why, in each chart's title).
  void clear(const QString& why);
  /// Moves the cursor of every chart to `t_s`.
  void set_cursor(double t_s);
  [[nodiscard]] double cursor_s() const { return cursor_s_; }

  /// The charts (force, speed, depth), for tests and screenshots.
  [[nodiscard]] QChartView* view(int i) const { return views_[static_cast<size_t>(i)]; }
  [[nodiscard]] QChart* chart(int i) const;
  /// Points drawn in chart i over all its data series (not counting cursor, events, limits).
  [[nodiscard]] int data_points(int i) const;

 private:
  struct Plot {
    QChart* chart = nullptr;
    QValueAxis* x = nullptr;
    QValueAxis* y = nullptr;
    std::vector<QLineSeries*> data;
    QLineSeries* cursor = nullptr;
    double top = 1.0;
  };
  Plot make_plot(int i, const QString& title, const QString& unit);
  void add_line(Plot& p, const std::vector<std::pair<double, double>>& xy, const QString& name,
                const QColor& color);
  void add_limit(Plot& p, double value, double t_end, const QString& name);
  void add_events(Plot& p, const sim::TaskState& task, double t_end);
  void finish(Plot& p, double t_end);

  std::array<QChartView*, 3> views_{};
  std::array<Plot, 3> plots_{};
  double cursor_s_ = 0.0;
};

}  // namespace lap::app
