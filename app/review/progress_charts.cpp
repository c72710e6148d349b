#include "app/review/progress_charts.h"

#include <QAreaSeries>
#include <QChart>
#include <QLegendMarker>
#include <QLineSeries>
#include <QPen>
#include <QScatterSeries>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <map>

namespace lap::app {

namespace {

struct Axes {
  QValueAxis* x = nullptr;
  QValueAxis* y = nullptr;
};

Axes reset(QChart* chart, const QString& title, const QString& metric) {
  chart->removeAllSeries();
  for (QAbstractAxis* a : chart->axes()) {
    chart->removeAxis(a);
    delete a;
  }
  chart->setTitle(title);
  Axes axes{new QValueAxis(), new QValueAxis()};
  axes.x->setTitleText(QObject::tr("session"));
  axes.x->setLabelFormat(QStringLiteral("%d"));
  axes.y->setTitleText(metric);
  axes.y->setLabelFormat(QStringLiteral("%.3g"));
  chart->addAxis(axes.x, Qt::AlignBottom);
  chart->addAxis(axes.y, Qt::AlignLeft);
  return axes;
}

void attach(QChart* chart, QAbstractSeries* s, const Axes& axes) {
  chart->addSeries(s);
  s->attachAxis(axes.x);
  s->attachAxis(axes.y);
}

// The experts' band from session 0.5 to n + 0.5, and the limit; widens [low, high] to hold it.
void draw_band(QChart* chart, const Axes& axes, const sim::MetricBenchmark& b, int n, double* low,
               double* high) {
  const double limit = b.higher_is_better ? b.mean - 2.0 * b.sd : b.mean + 2.0 * b.sd;
  auto* upper = new QLineSeries();
  auto* lower = new QLineSeries();
  upper->append(0.5, b.mean + 2.0 * b.sd);
  upper->append(n + 0.5, b.mean + 2.0 * b.sd);
  lower->append(0.5, b.mean - 2.0 * b.sd);
  lower->append(n + 0.5, b.mean - 2.0 * b.sd);
  auto* band = new QAreaSeries(upper, lower);
  upper->setParent(band);  // the area series does not own its edges
  lower->setParent(band);
  band->setName(QObject::tr("experts: mean ± 2 SD"));
  band->setBrush(QColor(200, 230, 200, 160));
  band->setPen(QPen(QColor(120, 180, 120), 0.5));
  attach(chart, band, axes);
  auto* line = new QLineSeries();
  line->setName(QObject::tr("proficiency limit %1").arg(limit, 0, 'g', 4));
  line->append(0.5, limit);
  line->append(n + 0.5, limit);
  line->setPen(QPen(QColor(204, 26, 26), 1.2, Qt::DashLine));
  attach(chart, line, axes);
  *low = std::min({*low, b.mean - 2.0 * b.sd, limit});
  *high = std::max({*high, b.mean + 2.0 * b.sd, limit});
}

void set_ranges(const Axes& axes, int n, double low, double high) {
  if (!std::isfinite(low) || !std::isfinite(high)) {
    low = 0.0;
    high = 1.0;
  }
  const double pad = high > low ? 0.08 * (high - low) : std::max(1e-6, 0.1 * std::abs(high));
  axes.x->setRange(0.5, std::max(1, n) + 0.5);
  // A tick on each session (1, 2, 3, …), or every 2, 5, 10, … of them for a long history; a
  // fixed count of ticks would put them between sessions (0.5, 2, 3.5) under a rounded label.
  int every = 1;
  for (const int m : {2, 5, 10, 20, 50, 100, 200, 500}) {
    if (n / every <= 12) break;
    every = m;
  }
  axes.x->setTickType(QValueAxis::TicksDynamic);
  axes.x->setTickAnchor(every == 1 ? 1.0 : 0.0);
  axes.x->setTickInterval(every);
  axes.y->setRange(low - pad, high + pad);
  axes.y->applyNiceNumbers();  // round values along the metric's axis
}

}  // namespace

int draw_learning_curve(QChart* chart, const QString& title, const std::vector<MetricPoint>& points,
                        const std::optional<sim::MetricBenchmark>& benchmark) {
  const Axes axes =
      reset(chart, title, benchmark ? QString::fromStdString(benchmark->metric) : QString());
  const int n = static_cast<int>(points.size());
  double low = INFINITY, high = -INFINITY;
  if (benchmark) draw_band(chart, axes, *benchmark, n, &low, &high);
  auto* curve = new QLineSeries();
  curve->setName(QObject::tr("sessions"));
  curve->setPen(QPen(QColor(26, 89, 204), 1.5));
  auto* met = new QScatterSeries();
  met->setName(QObject::tr("met"));
  met->setColor(QColor(13, 140, 51));
  met->setMarkerSize(9.0);
  auto* missed = new QScatterSeries();
  missed->setName(QObject::tr("not met"));
  missed->setColor(QColor(204, 26, 26));
  missed->setMarkerSize(9.0);
  const double limit = !benchmark                    ? 0.0
                       : benchmark->higher_is_better ? benchmark->mean - 2.0 * benchmark->sd
                                                     : benchmark->mean + 2.0 * benchmark->sd;
  for (int i = 0; i < n; ++i) {
    const double v = points[static_cast<size_t>(i)].value;
    if (!std::isfinite(v)) continue;
    curve->append(i + 1, v);
    low = std::min(low, v);
    high = std::max(high, v);
    if (benchmark) {
      const bool ok = benchmark->higher_is_better ? v >= limit : v <= limit;
      (ok ? met : missed)->append(i + 1, v);
    }
  }
  attach(chart, curve, axes);
  if (benchmark) {
    attach(chart, met, axes);
    attach(chart, missed, axes);
  } else {
    delete met;
    delete missed;
  }
  set_ranges(axes, n, low, high);
  return n;
}

int draw_cohort(QChart* chart, const QString& title, const std::vector<MetricPoint>& points,
                const std::optional<sim::MetricBenchmark>& benchmark) {
  const Axes axes =
      reset(chart, title, benchmark ? QString::fromStdString(benchmark->metric) : QString());
  std::map<QString, std::vector<MetricPoint>> by_trainee;
  for (const MetricPoint& p : points) by_trainee[p.trainee].push_back(p);
  int longest = 0;
  for (auto& [trainee, list] : by_trainee) {
    std::sort(list.begin(), list.end(), [](const MetricPoint& a, const MetricPoint& b) {
      return a.started_utc < b.started_utc;
    });
    longest = std::max(longest, static_cast<int>(list.size()));
  }
  double low = INFINITY, high = -INFINITY;
  if (benchmark) draw_band(chart, axes, *benchmark, longest, &low, &high);
  for (const auto& [trainee, list] : by_trainee) {
    auto* curve = new QLineSeries();
    curve->setName(trainee);
    curve->setPointsVisible(true);
    for (size_t i = 0; i < list.size(); ++i) {
      if (!std::isfinite(list[i].value)) continue;
      curve->append(static_cast<double>(i + 1), list[i].value);
      low = std::min(low, list[i].value);
      high = std::max(high, list[i].value);
    }
    attach(chart, curve, axes);
  }
  set_ranges(axes, longest, low, high);
  return static_cast<int>(by_trainee.size());
}

}  // namespace lap::app
