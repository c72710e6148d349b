#include "sim/report/session_pdf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/report/proficiency.h"

namespace lap::sim {

namespace {

constexpr double kLeft = 50.0;
constexpr double kWidth = PdfDocument::kPageWidthPt - 2.0 * kLeft;
constexpr PdfColor kInk{0.1, 0.1, 0.1};
constexpr PdfColor kGrey{0.55, 0.55, 0.55};
constexpr PdfColor kRed{0.80, 0.10, 0.10};
constexpr PdfColor kGreen{0.05, 0.55, 0.20};
constexpr PdfColor kBlue{0.10, 0.35, 0.80};
constexpr PdfColor kOrange{0.90, 0.50, 0.05};

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%.*f", digits, v);
  return text;
}

/// Four significant digits (a squeeze of 0.0003 N stays readable).
std::string significant(double v) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof(text), "%.4g", v);
  return text;
}

/// The metrics that count (movements, grasp attempts, drops, injury events): whole numbers.
bool is_count(const std::string& name) {
  for (const char* word : {"movements", "attempts", "drops", "events"}) {
    if (name.find(word) != std::string::npos) return true;
  }
  return false;
}

/// A tick step of 1, 2 or 5 × 10^k giving about five ticks up to `top`.
double tick_step(double top) {
  const double raw = top / 5.0;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10.0 * p;
}

struct Series {
  const std::vector<double>* values;
  double scale;  ///< to the plot's unit
  PdfColor color;
  std::string label;
};

struct Plot {
  std::string title;
  std::vector<Series> series;
  double threshold = 0.0;  ///< in the plot's unit; 0: none
  std::string threshold_label;
};

/// One plot in the box (x, y, w, h) over the series' times, the events as grey ticks.
void draw_plot(PdfDocument& doc, double y, double h, const Plot& plot, const MetricsSeries& s,
               const TaskState& task) {
  const double x = kLeft + 40.0, w = kWidth - 40.0;
  const double t_end = s.t_s.empty() ? 1.0 : std::max(s.t_s.back(), 1e-3);
  double top = plot.threshold * 1.15;
  for (const Series& v : plot.series) {
    for (const double value : *v.values) top = std::max(top, value * v.scale * 1.1);
  }
  if (!(top > 0.0)) top = 1.0;
  const double step = tick_step(top);
  top = std::ceil(top / step) * step;
  doc.text(kLeft, y - 6.0, plot.title, 10.0, true, kInk);
  const auto px = [&](double t) { return x + w * t / t_end; };
  const auto py = [&](double v) { return y + h - h * std::clamp(v / top, 0.0, 1.0); };
  for (double v = 0.0; v <= top + 1e-9 * top; v += step) {
    doc.line(x, py(v), x + w, py(v), 0.3, {0.85, 0.85, 0.85});
    doc.text(kLeft, py(v) + 3.0, fixed(v, step < 1.0 ? (step < 0.1 ? 2 : 1) : 0), 7.0, false,
             kGrey);
  }
  const double t_step = tick_step(t_end);
  for (double t = 0.0; t <= t_end + 1e-9; t += t_step) {
    doc.text(px(t) - 4.0, y + h + 10.0, fixed(t, t_step < 1.0 ? 1 : 0), 7.0, false, kGrey);
  }
  doc.text(x + w - 60.0, y + h + 20.0, "time [s]", 7.0, false, kGrey);
  for (const TaskEvent& e : task.events) {
    if (e.t_s <= t_end) doc.line(px(e.t_s), y, px(e.t_s), y + h, 0.4, {0.7, 0.7, 0.7}, true);
  }
  if (plot.threshold > 0.0) {
    doc.line(x, py(plot.threshold), x + w, py(plot.threshold), 0.8, kRed, true);
    doc.text(x + w - PdfDocument::text_width(plot.threshold_label, 7.0, false) - 4.0,
             py(plot.threshold) - 3.0, plot.threshold_label, 7.0, false, kRed);
  }
  double legend_x = x + w;
  for (auto it = plot.series.rbegin(); it != plot.series.rend(); ++it) {
    legend_x -= PdfDocument::text_width(it->label, 8.0, false) + 24.0;
    doc.line(legend_x, y - 9.0, legend_x + 14.0, y - 9.0, 1.5, it->color);
    doc.text(legend_x + 17.0, y - 6.0, it->label, 8.0, false, kInk);
    std::vector<double> xy;
    const size_t n = std::min(s.t_s.size(), it->values->size());
    for (size_t i = 0; i < n; ++i) {
      xy.push_back(px(s.t_s[i]));
      xy.push_back(py((*it->values)[i] * it->scale));
    }
    doc.polyline(xy, 1.0, it->color);
  }
  doc.line(x, y + h, x + w, y + h, 0.6, kInk);
  doc.line(x, y, x, y + h, 0.6, kInk);
}

/// Page one's head: what, where, the result and the phases. Returns where it ends.
double draw_head(PdfDocument& doc, const SessionMetrics& m, const SessionPdfContext& c) {
  doc.text(kLeft, 60.0, "laptrainer - session report", 18.0, true, kInk);
  doc.text(kLeft, 80.0, c.scenario_name, 11.0, false, kInk);
  doc.text(kLeft, 94.0, "scenario " + c.scenario_file, 8.0, false, kGrey);
  doc.text(kLeft, 105.0, "session " + c.session + " (" + c.mode + ")", 8.0, false, kGrey);
  const TaskState& t = m.task;
  std::string result = std::string(to_string(t.result));
  for (size_t i = 0; i < t.reason_count; ++i) {
    result += std::string(i == 0 ? ": " : ", ") + std::string(to_string(t.reasons[i]));
  }
  if (t.end_s >= 0.0) result += " at " + fixed(t.end_s, 2) + " s";
  const PdfColor color = t.result == TaskResult::kSuccess   ? kGreen
                         : t.result == TaskResult::kFailure ? kRed
                                                            : kInk;
  doc.text(kLeft, 132.0, result, 14.0, true, color);
  const char* const names[] = {"catheter grasped", "tip at the incision", "tip in the lumen",
                               "target depth reached", "held"};
  double y = 152.0;
  for (size_t p = 0; p < t.phase_s.size(); ++p) {
    doc.text(kLeft, y, names[p], 9.0, false, kInk);
    doc.text(kLeft + 130.0, y, t.phase_s[p] >= 0.0 ? fixed(t.phase_s[p], 2) + " s" : "not reached",
             9.0, false, kInk);
    y += 12.0;
  }
  for (const std::string& n : c.notes) {
    // Word-wrapped to the page's width.
    std::string line = "note:";
    size_t at = 0;
    while (at <= n.size()) {
      const size_t end = std::min(n.find(' ', at), n.size());
      const std::string word = n.substr(at, end - at);
      std::string wider = line;
      wider += ' ';
      wider += word;
      if (PdfDocument::text_width(wider, 7.0, false) > kWidth) {
        doc.text(kLeft, y, line, 7.0, false, kGrey);
        y += 9.0;
        line.clear();
      }
      line += (line.empty() ? "" : " ") + word;
      at = end + 1;
    }
    doc.text(kLeft, y, line, 7.0, false, kGrey);
    y += 10.0;
  }
  return y;
}

/// Page two: the metrics with their proficiency verdicts, then the events.
void draw_metrics_page(PdfDocument& doc, const SessionMetrics& m) {
  doc.new_page();
  doc.text(kLeft, 60.0, "Training metrics", 14.0, true, kInk);
  std::vector<BenchmarkResult> verdicts;
  if (m.proficiency) {
    verdicts = assess_proficiency(*m.proficiency, m.training);
    doc.text(kLeft, 74.0, "proficiency: " + m.proficiency->source, 6.5, false, kGrey);
  }
  double y = 92.0;
  doc.text(kLeft, y, "metric", 8.0, true, kInk);
  doc.text(kLeft + 250.0, y, "value", 8.0, true, kInk);
  doc.text(kLeft + 340.0, y, "expert limit", 8.0, true, kInk);
  doc.text(kLeft + 430.0, y, "verdict", 8.0, true, kInk);
  y += 11.0;
  for (const Metric& x : m.training) {
    if (y > PdfDocument::kPageHeightPt - 50.0) {
      doc.new_page();
      y = 60.0;
    }
    doc.text(kLeft, y, x.name, 7.5, false, kInk);
    doc.text(kLeft + 250.0, y,
             !std::isfinite(x.value) ? "null"
             : is_count(x.name)      ? fixed(x.value, 0)
                                     : significant(x.value),
             7.5, false, kInk);
    for (const BenchmarkResult& r : verdicts) {
      if (r.benchmark.metric != x.name) continue;
      doc.text(kLeft + 340.0, y,
               (r.benchmark.higher_is_better ? ">= " : "<= ") + significant(r.limit), 7.5, false,
               kInk);
      doc.text(kLeft + 430.0, y, r.met ? "met" : "NOT MET", 7.5, true, r.met ? kGreen : kRed);
    }
    y += 9.5;
  }
  y += 12.0;
  doc.text(kLeft, y, "Events", 11.0, true, kInk);
  y += 12.0;
  for (const TaskEvent& e : m.task.events) {
    if (y > PdfDocument::kPageHeightPt - 40.0) break;
    std::string what = std::string(to_string(e.kind));
    if (e.tool >= 0) what += e.tool == 0 ? " (left)" : " (right)";
    if (e.organ >= 0 && static_cast<size_t>(e.organ) < m.organ_names.size()) {
      what += " - " + m.organ_names[static_cast<size_t>(e.organ)];
    }
    doc.text(kLeft, y, fixed(e.t_s, 3) + " s", 7.5, false, kInk);
    doc.text(kLeft + 60.0, y, what, 7.5, false, kInk);
    y += 9.5;
  }
}

}  // namespace

PdfDocument session_pdf(const SessionMetrics& m, const SessionPdfContext& c) {
  PdfDocument doc;
  const double head_end = draw_head(doc, m, c);
  const MetricsSeries& s = m.series;
  const double plot_h = 125.0;
  double y = std::max(head_end + 24.0, 230.0);
  draw_plot(doc, y, plot_h,
            {"Force on the duct [N]",
             {{&s.duct_force_n, 1.0, kRed, "force"}, {&s.squeeze_n, 1.0, kBlue, "squeeze"}},
             c.duct_injury_force_n,
             "injury threshold " + fixed(c.duct_injury_force_n, 2) + " N"},
            s, m.task);
  y += plot_h + 50.0;
  draw_plot(doc, y, plot_h,
            {"Insertion depth [mm]",
             {{&s.depth_m, 1e3, kGreen, "depth"}},
             c.insertion_depth_m * 1e3,
             "target " + fixed(c.insertion_depth_m * 1e3, 1) + " mm"},
            s, m.task);
  y += plot_h + 50.0;
  draw_plot(
      doc, y, plot_h,
      {"Tool speed [mm/s]",
       {{&s.speed_m_per_s[0], 1e3, kBlue, "left"}, {&s.speed_m_per_s[1], 1e3, kOrange, "right"}},
       0.0,
       ""},
      s, m.task);
  draw_metrics_page(doc, m);
  return doc;
}

}  // namespace lap::sim
