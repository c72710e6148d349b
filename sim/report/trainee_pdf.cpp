#include "sim/report/trainee_pdf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lap::sim {

namespace {

constexpr double kLeft = 50.0;
constexpr double kWidth = PdfDocument::kPageWidthPt - 2.0 * kLeft;
constexpr double kBottom = PdfDocument::kPageHeightPt - 50.0;
constexpr PdfColor kInk{0.1, 0.1, 0.1};
constexpr PdfColor kGrey{0.55, 0.55, 0.55};
constexpr PdfColor kLight{0.85, 0.85, 0.85};
constexpr PdfColor kBand{0.86, 0.93, 0.86};
constexpr PdfColor kRed{0.80, 0.10, 0.10};
constexpr PdfColor kGreen{0.05, 0.55, 0.20};
constexpr PdfColor kBlue{0.10, 0.35, 0.80};

std::string significant(double v) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%.4g", v);
  return text;
}

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

/// A step of 1, 2 or 5 × 10^k giving about four ticks over `span`.
double tick_step(double span) {
  const double raw = span / 4.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

/// One learning curve in the box at y of height h: sessions along x (1, 2, ...), the metric up,
/// the experts' band (mean ± 2 SD) shaded and the limit dashed, each point green where met.
void draw_curve(PdfDocument& doc, double y, double h, const LearningCurve& c) {
  const double x = kLeft + 45.0, w = kWidth - 45.0;
  const size_t n = c.values.size();
  double low = INFINITY, high = -INFINITY;
  for (const double v : c.values) {
    if (!std::isfinite(v)) continue;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  if (c.progress) {
    const MetricBenchmark& b = c.progress->benchmark;
    low = std::min({low, b.mean - 2.0 * b.sd, c.progress->limit});
    high = std::max({high, b.mean + 2.0 * b.sd, c.progress->limit});
  }
  if (!std::isfinite(low) || !std::isfinite(high)) {
    low = 0.0;
    high = 1.0;
  }
  if (high - low < 1e-12) {
    high += 0.5 * std::max(1.0, std::abs(high));
    low -= 0.5 * std::max(1.0, std::abs(low));
  }
  const double step = tick_step(high - low);
  low = std::floor(low / step) * step;
  high = std::ceil(high / step) * step;
  std::string title = c.metric;
  if (c.progress) {
    title += c.progress->proficient_at >= 0
                 ? "  - proficient from session " + std::to_string(c.progress->proficient_at + 1)
                 : "  - not yet proficient";
  }
  doc.text(kLeft, y - 6.0, title, 9.5, true,
           c.progress ? (c.progress->proficient_at >= 0 ? kGreen : kRed) : kInk);
  const auto px = [&](double i) {
    return n <= 1 ? x + w / 2.0 : x + w * i / static_cast<double>(n - 1);
  };
  const auto py = [&](double v) {
    return y + h - h * std::clamp((v - low) / (high - low), 0.0, 1.0);
  };
  if (c.progress) {
    const MetricBenchmark& b = c.progress->benchmark;
    const double top = py(b.mean + 2.0 * b.sd), bottom = py(b.mean - 2.0 * b.sd);
    doc.fill_rect(x, top, w, bottom - top, kBand);
    doc.line(x, py(b.mean), x + w, py(b.mean), 0.5, kGreen);
    doc.line(x, py(c.progress->limit), x + w, py(c.progress->limit), 0.8, kRed, true);
    const std::string limit = (b.higher_is_better ? "limit >= " : "limit <= ") +
                              significant(c.progress->limit) + "   experts " + significant(b.mean) +
                              " +/- 2 x " + significant(b.sd);
    doc.text(x + w - PdfDocument::text_width(limit, 7.0, false), y - 6.0, limit, 7.0, false, kGrey);
  }
  for (double v = low; v <= high + 1e-9 * std::abs(high); v += step) {
    doc.line(x, py(v), x + w, py(v), 0.3, kLight);
    doc.text(kLeft, py(v) + 3.0, significant(v), 7.0, false, kGrey);
  }
  const size_t label_every = std::max<size_t>(1, n / 12);
  for (size_t i = 0; i < n; i += label_every) {
    doc.text(px(static_cast<double>(i)) - 3.0, y + h + 10.0, std::to_string(i + 1), 7.0, false,
             kGrey);
  }
  doc.text(x + w - 40.0, y + h + 20.0, "session", 7.0, false, kGrey);
  // The curve through the defined values, then each session's point.
  std::vector<double> xy;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(c.values[i])) continue;
    xy.push_back(px(static_cast<double>(i)));
    xy.push_back(py(c.values[i]));
  }
  doc.polyline(xy, 1.0, kBlue);
  for (size_t i = 0; i < n; ++i) {  // a session without the figure (e.g. no completion time)
    if (!std::isfinite(c.values[i])) {
      doc.text(px(static_cast<double>(i)) - 8.0, y + h - 4.0, "none", 6.5, false, kGrey);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(c.values[i])) continue;
    const bool met = c.progress && i < c.progress->met.size() && c.progress->met[i];
    const PdfColor color = !c.progress ? kBlue : met ? kGreen : kRed;
    doc.fill_rect(px(static_cast<double>(i)) - 2.5, py(c.values[i]) - 2.5, 5.0, 5.0, color);
  }
  doc.line(x, y + h, x + w, y + h, 0.6, kInk);
  doc.line(x, y, x, y + h, 0.6, kInk);
}

double draw_sessions(PdfDocument& doc, const TraineePdfContext& c, double y) {
  doc.text(kLeft, y, "Sessions", 11.0, true, kInk);
  y += 14.0;
  doc.text(kLeft, y, "#", 8.0, true, kInk);
  doc.text(kLeft + 20.0, y, "started", 8.0, true, kInk);
  doc.text(kLeft + 120.0, y, "result", 8.0, true, kInk);
  doc.text(kLeft + 330.0, y, "completion", 8.0, true, kInk);
  y += 11.0;
  for (size_t i = 0; i < c.sessions.size(); ++i) {
    if (y > kBottom) {
      doc.new_page();
      y = 60.0;
    }
    const TraineeSessionLine& s = c.sessions[i];
    std::string result = s.result;
    for (size_t k = 0; k < s.reasons.size(); ++k) result += (k == 0 ? ": " : ", ") + s.reasons[k];
    if (s.interrupted) result += " (interrupted)";
    const PdfColor color = s.result == "success" ? kGreen : s.result == "failure" ? kRed : kInk;
    doc.text(kLeft, y, std::to_string(i + 1), 7.5, false, kInk);
    doc.text(kLeft + 20.0, y, s.started, 7.5, false, kInk);
    doc.text(kLeft + 120.0, y, result, 7.5, false, color);
    doc.text(kLeft + 330.0, y,
             std::isfinite(s.completion_time_s) ? fixed(s.completion_time_s, 2) + " s" : "-", 7.5,
             false, kInk);
    y += 9.5;
  }
  return y;
}

/// Where the trainee stands on each benchmark: the limit, the latest value, which sessions met
/// it (oldest first) and since when proficient — the page an instructor reads first.
double draw_standing(PdfDocument& doc, const TraineePdfContext& c, double y) {
  std::vector<const LearningCurve*> benchmarked;
  for (const LearningCurve& curve : c.curves) {
    if (curve.progress) benchmarked.push_back(&curve);
  }
  if (benchmarked.empty()) return y;
  doc.text(kLeft, y, "Against the experts", 11.0, true, kInk);
  y += 14.0;
  doc.text(kLeft, y, "metric", 8.0, true, kInk);
  doc.text(kLeft + 150.0, y, "limit", 8.0, true, kInk);
  doc.text(kLeft + 220.0, y, "latest", 8.0, true, kInk);
  doc.text(kLeft + 280.0, y, "met in sessions (oldest first)", 8.0, true, kInk);
  doc.text(kLeft + 420.0, y, "proficient", 8.0, true, kInk);
  y += 11.0;
  for (const LearningCurve* curve : benchmarked) {
    const ProficiencyProgress& p = *curve->progress;
    double latest = NAN;
    for (const double v : curve->values) {
      if (std::isfinite(v)) latest = v;
    }
    doc.text(kLeft, y, curve->metric, 7.5, false, kInk);
    doc.text(kLeft + 150.0, y,
             (p.benchmark.higher_is_better ? ">= " : "<= ") + significant(p.limit), 7.5, false,
             kInk);
    doc.text(kLeft + 220.0, y, significant(latest), 7.5, false, kInk);
    // One mark per session: a green "yes" where met, a red "no" where not, "-" where undefined.
    double x = kLeft + 280.0;
    for (size_t i = 0; i < p.met.size(); ++i) {
      const bool defined = i < p.values.size() && std::isfinite(p.values[i]);
      const std::string mark = !defined ? "-" : p.met[i] ? "yes" : "no";
      doc.text(x, y, mark, 7.5, false, !defined ? kGrey : p.met[i] ? kGreen : kRed);
      x += 18.0;
      if (x > kLeft + 410.0) break;  // a long history: the curves show the rest
    }
    doc.text(
        kLeft + 420.0, y,
        p.proficient_at >= 0 ? "from session " + std::to_string(p.proficient_at + 1) : "not yet",
        7.5, false, p.proficient_at >= 0 ? kGreen : kRed);
    y += 9.5;
  }
  return y;
}

}  // namespace

PdfDocument trainee_pdf(const TraineePdfContext& c) {
  PdfDocument doc;
  doc.text(kLeft, 60.0, "laptrainer - trainee report", 18.0, true, kInk);
  doc.text(kLeft, 80.0, c.trainee, 12.0, true, kInk);
  doc.text(kLeft, 94.0, c.scenario_name, 10.0, false, kInk);
  doc.text(kLeft, 106.0, "scenario " + c.scenario_file, 8.0, false, kGrey);
  double y = 126.0;
  std::vector<ProficiencyProgress> benchmarked;
  for (const LearningCurve& curve : c.curves) {
    if (curve.progress) benchmarked.push_back(*curve.progress);
  }
  if (!benchmarked.empty()) {
    const int at = proficient_at(benchmarked);
    int met = 0;
    for (const ProficiencyProgress& p : benchmarked) met += p.proficient_at >= 0 ? 1 : 0;
    const std::string verdict = at >= 0 ? "Proficient from session " + std::to_string(at + 1) +
                                              " (every benchmark met in two consecutive sessions)"
                                        : "Not yet proficient: " + std::to_string(met) + " of " +
                                              std::to_string(benchmarked.size()) +
                                              " benchmarks met in two consecutive sessions";
    doc.text(kLeft, y, verdict, 12.0, true, at >= 0 ? kGreen : kRed);
    y += 12.0;
    if (!c.proficiency_source.empty()) {
      doc.text(kLeft, y, "experts: " + c.proficiency_source, 6.5, false, kGrey);
      y += 10.0;
    }
  } else {
    doc.text(kLeft, y, "The scenario has no expert benchmarks: no proficiency verdict.", 10.0,
             false, kInk);
    y += 12.0;
  }
  for (const std::string& note : c.notes) {
    doc.text(kLeft, y, "note: " + note, 7.0, false, kGrey);
    y += 9.0;
  }
  y = draw_sessions(doc, c, y + 14.0);
  y = draw_standing(doc, c, y + 14.0);

  // The learning curves, benchmarked ones first, three to a page.
  std::vector<const LearningCurve*> order;
  for (const LearningCurve& curve : c.curves) {
    if (curve.progress) order.push_back(&curve);
  }
  for (const LearningCurve& curve : c.curves) {
    if (!curve.progress) order.push_back(&curve);
  }
  constexpr double kPlotH = 170.0;
  constexpr double kPlotGap = 75.0;
  // The first curves below the tables, on the first page where they fit.
  y += 24.0;
  if (!order.empty() && y + kPlotH + 60.0 <= kBottom) {
    doc.text(kLeft, y, "Learning curves", 11.0, true, kInk);
    y += 30.0;
  } else {
    y = kBottom;
  }
  for (const LearningCurve* curve : order) {
    if (y + kPlotH + 30.0 > kBottom) {
      doc.new_page();
      doc.text(kLeft, 50.0, "Learning curves - " + c.trainee, 12.0, true, kInk);
      y = 90.0;
    }
    draw_curve(doc, y, kPlotH, *curve);
    y += kPlotH + kPlotGap;
  }
  return doc;
}

}  // namespace lap::sim
