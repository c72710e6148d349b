#include "app/hud_overlay.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#include <vtkTextProperty.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lap::app {
namespace {

constexpr int kVignetteSegments = 48;
constexpr int kQuadsPerHand = 6;  // force: back, fill, tick; squeeze: back, fill, tick

void set_text(vtkTextActor* a, const std::string& s) {
  const char* now = a->GetInput();
  if (now == nullptr || s != now) a->SetInput(s.c_str());
}

std::string fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

void set_quad(vtkPoints* points, vtkIdType quad, double x0, double y0, double x1, double y1) {
  const vtkIdType p = 4 * quad;
  points->SetPoint(p, x0, y0, 0.0);
  points->SetPoint(p + 1, x1, y0, 0.0);
  points->SetPoint(p + 2, x1, y1, 0.0);
  points->SetPoint(p + 3, x0, y1, 0.0);
}

void set_colour(vtkUnsignedCharArray* c, vtkIdType quad, double r, double g, double b, double a) {
  c->SetTuple4(quad, 255.0 * r, 255.0 * g, 255.0 * b, 255.0 * a);
}

// The bar's colour: green, amber from 80 % of the threshold, red over it.
Eigen::Vector3d gauge_colour(double fraction) {
  if (fraction > 1.0) return {1.0, 0.22, 0.18};
  if (fraction >= 0.8) return {1.0, 0.72, 0.15};
  return {0.35, 0.85, 0.45};
}

// The bar shows up to 1.5 times the threshold; the threshold is marked at two thirds.
constexpr double kBarSpan = 1.5;

}  // namespace

HudLayout HudLayout::for_size(int width_px, int height_px) {
  HudLayout l;
  const double w = std::max(width_px, 1);
  const double h = std::max(height_px, 1);
  l.margin_px = std::round(0.02 * h);
  l.font_px = std::max(12.0, std::round(0.026 * h));
  l.small_font_px = std::max(10.0, std::round(0.02 * h));
  l.big_font_px = std::max(14.0, std::round(0.034 * h));
  l.gauge_width_px = std::round(0.24 * w);
  l.force_bar_px = std::max(6.0, std::round(0.02 * h));
  l.squeeze_bar_px = std::max(4.0, std::round(0.011 * h));
  l.free_x0 = 0.15 * w;
  l.free_x1 = 0.85 * w;
  l.free_y0 = 0.2 * h;
  l.free_y1 = 0.78 * h;
  return l;
}

vtkSmartPointer<vtkTextActor> HudOverlay::text(double size_px, bool bold) {
  auto a = vtkSmartPointer<vtkTextActor>::New();
  a->SetTextScaleModeToNone();
  vtkTextProperty* p = a->GetTextProperty();
  p->SetFontFamilyToArial();
  p->SetFontSize(static_cast<int>(size_px));
  p->SetBold(bold);
  p->SetShadow(true);
  p->SetColor(1.0, 1.0, 1.0);
  p->SetBackgroundColor(0.0, 0.0, 0.0);
  p->SetBackgroundOpacity(0.35);
  a->SetInput("");
  renderer_->AddActor2D(a);
  return a;
}

void HudOverlay::attach(vtkRenderer* renderer) {
  renderer_ = renderer;
  // The vignette: two rings of points round the picture's centre (transparent inside, dark at
  // the corners), the quads between them coloured per point.
  vignette_poly_ = vtkSmartPointer<vtkPolyData>::New();
  {
    vtkNew<vtkPoints> points;
    points->SetNumberOfPoints(2 * kVignetteSegments);
    vtkNew<vtkCellArray> quads;
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetNumberOfComponents(4);
    colours->SetNumberOfTuples(2 * kVignetteSegments);
    for (int k = 0; k < kVignetteSegments; ++k) {
      const vtkIdType a = 2 * k;
      const vtkIdType b = 2 * ((k + 1) % kVignetteSegments);
      const vtkIdType ids[4] = {a, b, b + 1, a + 1};
      quads->InsertNextCell(4, ids);
      colours->SetTuple4(a, 0, 0, 0, 0);
      colours->SetTuple4(a + 1, 0, 0, 0, 235);
    }
    vignette_poly_->SetPoints(points);
    vignette_poly_->SetPolys(quads);
    vignette_poly_->GetPointData()->SetScalars(colours);
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(vignette_poly_);
    mapper->SetColorModeToDirectScalars();
    vignette_ = vtkSmartPointer<vtkActor2D>::New();
    vignette_->SetMapper(mapper);
    renderer->AddActor2D(vignette_);
  }
  // The gauges' quads, coloured per quad.
  bars_ = vtkSmartPointer<vtkPolyData>::New();
  {
    constexpr int kQuads = 2 * kQuadsPerHand;
    vtkNew<vtkPoints> points;
    points->SetNumberOfPoints(4 * kQuads);
    for (vtkIdType p = 0; p < 4 * kQuads; ++p) points->SetPoint(p, 0.0, 0.0, 0.0);
    vtkNew<vtkCellArray> quads;
    for (vtkIdType q = 0; q < kQuads; ++q) {
      const vtkIdType ids[4] = {4 * q, 4 * q + 1, 4 * q + 2, 4 * q + 3};
      quads->InsertNextCell(4, ids);
    }
    bar_colours_ = vtkSmartPointer<vtkUnsignedCharArray>::New();
    bar_colours_->SetNumberOfComponents(4);
    bar_colours_->SetNumberOfTuples(kQuads);
    bar_colours_->FillValue(0);
    bars_->SetPoints(points);
    bars_->SetPolys(quads);
    bars_->GetCellData()->SetScalars(bar_colours_);
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(bars_);
    mapper->SetColorModeToDirectScalars();
    mapper->SetScalarModeToUseCellData();
    bars_actor_ = vtkSmartPointer<vtkActor2D>::New();
    bars_actor_->SetMapper(mapper);
    renderer->AddActor2D(bars_actor_);
  }
  const HudLayout l = HudLayout::for_size(1280, 720);
  step_ = text(l.small_font_px, false);
  step_->GetTextProperty()->SetColor(0.55, 0.85, 1.0);
  instruction_ = text(l.font_px, true);
  progress_ = text(l.font_px, false);
  progress_->GetTextProperty()->SetColor(1.0, 0.9, 0.45);
  timer_ = text(l.big_font_px, true);
  scope_ = text(l.small_font_px, false);
  scope_->GetTextProperty()->SetColor(0.7, 0.7, 0.7);
  result_ = text(l.big_font_px, true);
  result_->GetTextProperty()->SetBackgroundOpacity(0.6);
  loops_ = text(l.small_font_px, false);
  for (size_t i = 0; i < 2; ++i) {
    gauge_labels_[i] = text(l.font_px, false);
    squeeze_labels_[i] = text(l.small_font_px, false);
    squeeze_labels_[i]->GetTextProperty()->SetColor(0.8, 0.8, 0.8);
  }
  for (auto& n : notices_) n = text(l.font_px, true);
  for (vtkTextActor* a : {timer_.Get(), scope_.Get()}) {
    a->GetTextProperty()->SetJustificationToRight();
  }
  for (vtkTextActor* a : {result_.Get(), loops_.Get()}) {
    a->GetTextProperty()->SetJustificationToCentered();
  }
  for (auto& n : notices_) n->GetTextProperty()->SetJustificationToCentered();
  gauge_labels_[1]->GetTextProperty()->SetJustificationToRight();
  squeeze_labels_[1]->GetTextProperty()->SetJustificationToRight();
  for (vtkTextActor* a : {step_.Get(), instruction_.Get(), progress_.Get(), timer_.Get(),
                          scope_.Get(), result_.Get()}) {
    a->GetTextProperty()->SetVerticalJustificationToTop();
  }
}

void HudOverlay::set_visible(bool visible) {
  vignette_->SetVisibility(visible);
  bars_actor_->SetVisibility(visible);
  for (vtkTextActor* a : texts()) a->SetVisibility(visible);
}

std::vector<vtkTextActor*> HudOverlay::texts() const {
  std::vector<vtkTextActor*> all = {step_,  instruction_, progress_, timer_,
                                    scope_, result_,      loops_};
  for (size_t i = 0; i < 2; ++i) {
    all.push_back(gauge_labels_[i]);
    all.push_back(squeeze_labels_[i]);
  }
  for (const auto& n : notices_) all.push_back(n);
  return all;
}

void HudOverlay::draw(const HudState& state, int width_px, int height_px) {
  if (renderer_ == nullptr) return;
  const HudLayout l = HudLayout::for_size(width_px, height_px);
  const double w = width_px;
  const double h = height_px;
  if (width_px != width_ || height_px != height_) {
    width_ = width_px;
    height_ = height_px;
    // Sizes and the vignette follow the window.
    auto size = [](vtkTextActor* a, double px) {
      a->GetTextProperty()->SetFontSize(static_cast<int>(px));
    };
    for (vtkTextActor* a :
         {instruction_.Get(), progress_.Get(), gauge_labels_[0].Get(), gauge_labels_[1].Get()}) {
      size(a, l.font_px);
    }
    for (const auto& n : notices_) size(n, l.font_px);
    for (vtkTextActor* a : {step_.Get(), scope_.Get(), loops_.Get(), squeeze_labels_[0].Get(),
                            squeeze_labels_[1].Get()}) {
      size(a, l.small_font_px);
    }
    size(timer_, l.big_font_px);
    size(result_, l.big_font_px);
    const double cx = 0.5 * w;
    const double cy = 0.5 * h;
    const double corner = std::hypot(cx, cy) + 2.0;
    vtkPoints* points = vignette_poly_->GetPoints();
    for (int k = 0; k < kVignetteSegments; ++k) {
      const double a = 2.0 * M_PI * k / kVignetteSegments;
      // Darkening starts at 80 % of the half height and is nearly black at the corners.
      const double inner = 0.8 * std::min(cx, cy) + 0.35 * (corner - std::min(cx, cy));
      points->SetPoint(2 * k, cx + inner * std::cos(a), cy + inner * std::sin(a), 0.0);
      points->SetPoint(2 * k + 1, cx + corner * std::cos(a), cy + corner * std::sin(a), 0.0);
    }
    points->Modified();
  }
  const double m = l.margin_px;
  // Top left: step, instruction, progress.
  set_text(step_, state.step);
  step_->SetDisplayPosition(static_cast<int>(m), static_cast<int>(h - m));
  set_text(instruction_, state.instruction);
  instruction_->SetDisplayPosition(static_cast<int>(m),
                                   static_cast<int>(h - m - 1.5 * l.small_font_px));
  set_text(progress_, state.progress);
  progress_->SetDisplayPosition(static_cast<int>(m),
                                static_cast<int>(h - m - 1.5 * l.small_font_px - 1.45 * l.font_px));
  // Top right: the timer and the scope.
  set_text(timer_, state.timer);
  timer_->SetDisplayPosition(static_cast<int>(w - m), static_cast<int>(h - m));
  set_text(scope_, state.scope);
  scope_->SetDisplayPosition(static_cast<int>(w - m),
                             static_cast<int>(h - m - 1.4 * l.big_font_px));
  // The result, below the top rows, in the middle of the width.
  set_text(result_, state.result);
  result_->SetDisplayPosition(static_cast<int>(0.5 * w),
                              static_cast<int>(h - m - 1.5 * l.small_font_px - 2.9 * l.font_px));
  if (state.failed) {
    result_->GetTextProperty()->SetColor(1.0, 0.35, 0.3);
  } else {
    result_->GetTextProperty()->SetColor(0.45, 1.0, 0.5);
  }
  // Bottom middle: the loops' note, the notices above it (newest lowest).
  set_text(loops_, state.loops);
  loops_->SetDisplayPosition(static_cast<int>(0.5 * w), static_cast<int>(m));
  if (state.loops_alarm) {
    loops_->GetTextProperty()->SetColor(1.0, 0.35, 0.3);
    loops_->GetTextProperty()->SetBold(true);
    loops_->GetTextProperty()->SetFontSize(static_cast<int>(l.font_px));
  } else {
    loops_->GetTextProperty()->SetColor(0.6, 0.6, 0.6);
    loops_->GetTextProperty()->SetBold(false);
    loops_->GetTextProperty()->SetFontSize(static_cast<int>(l.small_font_px));
  }
  const size_t shown = state.notices.size();
  for (size_t k = 0; k < notices_.size(); ++k) {
    vtkTextActor* a = notices_[k];
    if (k >= shown) {
      set_text(a, "");
      continue;
    }
    const HudNotice& n = state.notices[shown - 1 - k];  // newest first, lowest
    set_text(a, n.text);
    a->SetDisplayPosition(
        static_cast<int>(0.5 * w),
        static_cast<int>(m + 1.6 * l.font_px + static_cast<double>(k) * 1.5 * l.font_px));
    vtkTextProperty* p = a->GetTextProperty();
    if (n.alarm) {
      p->SetColor(1.0, 0.4, 0.35);
    } else {
      p->SetColor(0.9, 0.95, 1.0);
    }
    p->SetOpacity(n.opacity);
    p->SetBackgroundOpacity(0.45 * n.opacity);
  }
  place_gauges(state, l, width_px);
}

void HudOverlay::place_gauges(const HudState& state, const HudLayout& l, int width_px) {
  vtkPoints* points = bars_->GetPoints();
  const double m = l.margin_px;
  for (size_t i = 0; i < 2; ++i) {
    const HandGauge& g = state.hands[i];
    const double x0 = i == 0 ? m : width_px - m - l.gauge_width_px;
    const double x1 = x0 + l.gauge_width_px;
    const auto q = static_cast<vtkIdType>(i * kQuadsPerHand);
    // Squeeze bar at the bottom, its label above it, the force bar above that, its label on top.
    const double sq0 = m;
    const double sq1 = sq0 + l.squeeze_bar_px;
    const double sq_label = sq1 + 3.0;
    const double f0 = sq_label + 1.3 * l.small_font_px + 4.0;
    const double f1 = f0 + l.force_bar_px;
    auto bar = [&](vtkIdType first, double y0, double y1, double fraction) {
      const double fill = std::clamp(fraction / kBarSpan, 0.0, 1.0);
      const double tick = x0 + (x1 - x0) / kBarSpan;
      set_quad(points, first, x0, y0, x1, y1);
      set_colour(bar_colours_, first, 0.0, 0.0, 0.0, 0.45);
      set_quad(points, first + 1, x0, y0, x0 + fill * (x1 - x0), y1);
      const Eigen::Vector3d rgb = gauge_colour(fraction);
      set_colour(bar_colours_, first + 1, rgb.x(), rgb.y(), rgb.z(), 0.9);
      set_quad(points, first + 2, tick - 1.0, y0 - 2.0, tick + 1.0, y1 + 2.0);
      set_colour(bar_colours_, first + 2, 1.0, 1.0, 1.0, 0.95);
    };
    bar(q, f0, f1, g.fraction);
    if (g.jaws) {
      bar(q + 3, sq0, sq1, g.squeeze_threshold_n > 0.0 ? g.squeeze_n / g.squeeze_threshold_n : 0.0);
    } else {  // a probe has no jaws: no squeeze bar
      for (vtkIdType k = q + 3; k < q + 6; ++k) {
        set_quad(points, k, x0, sq0, x0, sq0);
        set_colour(bar_colours_, k, 0.0, 0.0, 0.0, 0.0);
      }
    }
    std::string label = g.label + "  " + fixed(g.force_n, 1) + " N";
    if (!g.pushing.empty()) label += " on " + g.pushing;
    label += "  (injury " + fixed(g.threshold_n, 1) + " N)";
    set_text(gauge_labels_[i], label);
    gauge_labels_[i]->SetDisplayPosition(static_cast<int>(i == 0 ? x0 : x1),
                                         static_cast<int>(f1 + 4.0));
    if (g.over) {
      gauge_labels_[i]->GetTextProperty()->SetColor(1.0, 0.4, 0.35);
    } else {
      gauge_labels_[i]->GetTextProperty()->SetColor(1.0, 1.0, 1.0);
    }
    set_text(squeeze_labels_[i], g.jaws ? "squeeze " + fixed(g.squeeze_n, 1) + " N  (crush " +
                                              fixed(g.squeeze_threshold_n, 1) + " N)"
                                        : std::string());
    squeeze_labels_[i]->SetDisplayPosition(static_cast<int>(i == 0 ? x0 : x1),
                                           static_cast<int>(sq_label));
  }
  points->Modified();
  bar_colours_->Modified();
}

}  // namespace lap::app
