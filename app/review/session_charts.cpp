#include "app/review/session_charts.h"

#include <QChart>
#include <QChartView>
#include <QLegend>
#include <QLegendMarker>
#include <QLineSeries>
#include <QPainter>
#include <QPen>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <array>
#include <cmath>

namespace lap::app {

namespace {

const QColor kForce(204, 26, 26);
const QColor kSqueeze(26, 89, 204);
const QColor kLeft(26, 89, 204);
const QColor kRight(230, 128, 13);
const QColor kDepth(13, 140, 51);

void hide_from_legend(QChart* chart, QAbstractSeries* s) {
  for (QLegendMarker* m : chart->legend()->markers(s)) m->setVisible(false);
}

}  // namespace

std::vector<std::pair<double, double>> thin_series(const std::vector<double>& t_s,
                                                   const std::vector<double>& v, double scale,
                                                   size_t max_points) {
  const size_t n = std::min(t_s.size(), v.size());
  std::vector<std::pair<double, double>> out;
  if (n == 0) return out;
  if (n <= max_points || max_points < 3) {
    out.reserve(n);
    for (size_t i = 0; i < n; ++i) out.emplace_back(t_s[i], v[i] * scale);
    return out;
  }
  // Buckets of equal count; each gives its first sample and its extremes, in time order.
  const size_t buckets = max_points / 3;
  out.reserve(3 * buckets + 1);
  for (size_t b = 0; b < buckets; ++b) {
    const size_t from = b * n / buckets, to = (b + 1) * n / buckets;
    size_t lo = from, hi = from;
    for (size_t i = from; i < to; ++i) {
      if (v[i] < v[lo]) lo = i;
      if (v[i] > v[hi]) hi = i;
    }
    std::array<size_t, 3> picks{from, std::min(lo, hi), std::max(lo, hi)};
    size_t last = n;  // none yet
    for (const size_t i : picks) {
      if (i == last) continue;
      out.emplace_back(t_s[i], v[i] * scale);
      last = i;
    }
  }
  out.emplace_back(t_s[n - 1], v[n - 1] * scale);
  return out;
}

SessionCharts::SessionCharts(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  const char* const titles[] = {"Force on the duct", "Tool speed", "Insertion depth"};
  for (size_t i = 0; i < 3; ++i) {
    auto* chart = new QChart();
    chart->setTitle(QString::fromLatin1(titles[i]));
    chart->legend()->setAlignment(Qt::AlignRight);
    chart->setMargins(QMargins(2, 2, 2, 2));
    views_[i] = new QChartView(chart, this);
    views_[i]->setRenderHint(QPainter::Antialiasing);
    views_[i]->setMinimumHeight(140);
    views_[i]->setObjectName(QStringLiteral("chart%1").arg(i));
    layout->addWidget(views_[i]);
    plots_[i].chart = chart;
  }
  clear(tr("no session selected"));
}

QChart* SessionCharts::chart(int i) const { return plots_[static_cast<size_t>(i)].chart; }

int SessionCharts::data_points(int i) const {
  int n = 0;
  for (const QLineSeries* s : plots_[static_cast<size_t>(i)].data)
    n += static_cast<int>(s->count());
  return n;
}

SessionCharts::Plot SessionCharts::make_plot(int i, const QString& title, const QString& unit) {
  Plot p;
  p.chart = plots_[static_cast<size_t>(i)].chart;
  p.chart->removeAllSeries();
  for (QAbstractAxis* a : p.chart->axes()) {
    p.chart->removeAxis(a);
    delete a;
  }
  p.chart->setTitle(title);
  p.x = new QValueAxis();
  p.x->setTitleText(tr("time [s]"));
  p.x->setLabelFormat(QStringLiteral("%.3g"));
  p.y = new QValueAxis();
  p.y->setTitleText(unit);
  p.y->setLabelFormat(QStringLiteral("%.3g"));
  p.chart->addAxis(p.x, Qt::AlignBottom);
  p.chart->addAxis(p.y, Qt::AlignLeft);
  return p;
}

void SessionCharts::add_line(Plot& p, const std::vector<std::pair<double, double>>& xy,
                             const QString& name, const QColor& color) {
  auto* s = new QLineSeries();
  s->setName(name);
  QList<QPointF> points;
  points.reserve(static_cast<qsizetype>(xy.size()));
  for (const auto& [t, v] : xy) {
    if (!std::isfinite(v)) continue;
    points.append(QPointF(t, v));
    p.top = std::max(p.top, v);
  }
  s->replace(points);
  s->setPen(QPen(color, 1.3));
  p.chart->addSeries(s);
  s->attachAxis(p.x);
  s->attachAxis(p.y);
  p.data.push_back(s);
}

void SessionCharts::add_limit(Plot& p, double value, double t_end, const QString& name) {
  if (!(value > 0.0)) return;
  auto* s = new QLineSeries();
  s->setName(name);
  s->append(0.0, value);
  s->append(t_end, value);
  s->setProperty("limit", true);
  QPen pen(QColor(204, 26, 26), 1.2, Qt::DashLine);
  s->setPen(pen);
  p.chart->addSeries(s);
  s->attachAxis(p.x);
  s->attachAxis(p.y);
  p.top = std::max(p.top, value * 1.15);
}

void SessionCharts::add_events(Plot& p, const sim::TaskState& task, double t_end) {
  // Each event a dashed grey line across the plot, named for its tooltip; the legend shows one.
  bool first = true;
  for (const sim::TaskEvent& e : task.events) {
    if (e.t_s > t_end) continue;
    auto* s = new QLineSeries();
    s->setName(first ? tr("events") : QString::fromLatin1(sim::to_string(e.kind).data()));
    s->append(e.t_s, 0.0);
    s->append(e.t_s, 1.0);  // rescaled in finish()
    s->setPen(QPen(QColor(150, 150, 150), 0.8, Qt::DotLine));
    s->setProperty("event", true);
    s->setProperty("kind", QString::fromLatin1(sim::to_string(e.kind).data()));
    p.chart->addSeries(s);
    s->attachAxis(p.x);
    s->attachAxis(p.y);
    if (!first) hide_from_legend(p.chart, s);
    first = false;
  }
}

void SessionCharts::finish(Plot& p, double t_end) {
  p.top = p.top > 0.0 ? p.top * 1.05 : 1.0;
  for (QAbstractSeries* a : p.chart->series()) {
    auto* s = qobject_cast<QLineSeries*>(a);
    if (s != nullptr && s->property("event").toBool()) s->replace(1, QPointF(s->at(1).x(), p.top));
  }
  p.cursor = new QLineSeries();
  p.cursor->setName(tr("replay"));
  p.cursor->append(cursor_s_, 0.0);
  p.cursor->append(cursor_s_, p.top);
  p.cursor->setPen(QPen(QColor(20, 20, 20), 1.5));
  p.chart->addSeries(p.cursor);
  p.cursor->attachAxis(p.x);
  p.cursor->attachAxis(p.y);
  p.x->setRange(0.0, std::max(t_end, 1e-3));
  p.y->setRange(0.0, p.top);
  // Round ticks (0, 0.5, 1 N rather than 0.604, 1.21). Up, the axis may grow a little past the
  // data; along time it ends with the session, its ticks every 1, 2 or 5 × 10^k s from 0.
  p.y->applyNiceNumbers();
  const double raw_step = std::max(t_end, 1e-3) / 5.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw_step)));
  double step = 10.0 * decade;
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw_step) {
      step = m * decade;
      break;
    }
  }
  p.x->setTickType(QValueAxis::TicksDynamic);
  p.x->setTickAnchor(0.0);
  p.x->setTickInterval(step);
  p.top = p.y->max();
  for (QAbstractSeries* a : p.chart->series()) {
    auto* s = qobject_cast<QLineSeries*>(a);
    if (s != nullptr && (s->property("event").toBool() || s == p.cursor)) {
      s->replace(1, QPointF(s->at(1).x(), p.top));
    }
    if (s != nullptr && s->property("limit").toBool()) {
      s->replace(1, QPointF(p.x->max(), s->at(1).y()));  // across the whole plot
    }
  }
}

void SessionCharts::set_session(const sim::MetricsSeries& s, const sim::TaskState& task,
                                double duct_injury_force_n, double insertion_depth_m) {
  const double t_end = s.t_s.empty() ? 1.0 : std::max(s.t_s.back(), 1e-3);
  cursor_s_ = 0.0;
  Plot force = make_plot(0, tr("Force on the duct"), tr("N"));
  add_line(force, thin_series(s.t_s, s.duct_force_n, 1.0, kMaxPoints), tr("force"), kForce);
  add_line(force, thin_series(s.t_s, s.squeeze_n, 1.0, kMaxPoints), tr("squeeze"), kSqueeze);
  add_limit(force, duct_injury_force_n, t_end,
            tr("injury threshold %1 N").arg(duct_injury_force_n, 0, 'g', 3));
  add_events(force, task, t_end);
  finish(force, t_end);
  plots_[0] = force;

  Plot speed = make_plot(1, tr("Tool speed"), tr("mm/s"));
  add_line(speed, thin_series(s.t_s, s.speed_m_per_s[0], 1e3, kMaxPoints), tr("left"), kLeft);
  add_line(speed, thin_series(s.t_s, s.speed_m_per_s[1], 1e3, kMaxPoints), tr("right"), kRight);
  add_events(speed, task, t_end);
  finish(speed, t_end);
  plots_[1] = speed;

  Plot depth = make_plot(2, tr("Insertion depth"), tr("mm"));
  add_line(depth, thin_series(s.t_s, s.depth_m, 1e3, kMaxPoints), tr("depth"), kDepth);
  add_limit(depth, insertion_depth_m * 1e3, t_end,
            tr("target %1 mm").arg(insertion_depth_m * 1e3, 0, 'g', 3));
  add_events(depth, task, t_end);
  finish(depth, t_end);
  plots_[2] = depth;
}

void SessionCharts::clear(const QString& why) {
  const char* const titles[] = {"Force on the duct", "Tool speed", "Insertion depth"};
  for (size_t i = 0; i < 3; ++i) {
    Plot p = make_plot(static_cast<int>(i), tr(titles[i]) + QStringLiteral(" - ") + why, QString());
    plots_[i] = p;
  }
}

void SessionCharts::set_cursor(double t_s) {
  cursor_s_ = t_s;
  for (Plot& p : plots_) {
    if (p.cursor == nullptr) continue;
    p.cursor->replace(0, QPointF(t_s, 0.0));
    p.cursor->replace(1, QPointF(t_s, p.top));
  }
}

}  // namespace lap::app
