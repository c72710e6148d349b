#pragma once
/// \file
/// The heads-up display drawn into the render window with VTK's 2D actors (so a screenshot
/// shows it): the instruction, step and progress at the top left; the timer and the scope's
/// settings at the top right; the result below the top edge's middle when the task ends; a force
/// gauge per hand at the bottom corners (the bar against its injury threshold, marked, and the
/// jaws' squeeze against the duct's crush threshold); event notices and the loops' quiet note at
/// the bottom's middle. Nothing is drawn over the middle of the picture, where the operative
/// field is (HudLayout keeps every element in a band along the edges, and a test checks it).
/// A laparoscope's optics darken the picture's corners: a soft vignette is drawn first.
///
/// Texts are re-rendered only when they change; the bars are a few quads moved in place.

#include <vtkActor2D.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkUnsignedCharArray.h>

#include <array>
#include <string>
#include <vector>

#include "app/hud_state.h"

namespace lap::app {

/// Where the display's elements go for a picture of width x height pixels (origin bottom left).
struct HudLayout {
  double margin_px = 0.0;
  double font_px = 0.0;        ///< instruction, gauges' labels, notices
  double small_font_px = 0.0;  ///< step, scope, loops, squeeze
  double big_font_px = 0.0;    ///< timer, result
  double gauge_width_px = 0.0;
  double force_bar_px = 0.0;    ///< height of the force bar
  double squeeze_bar_px = 0.0;  ///< height of the squeeze bar
  /// The band along the edges everything stays in: nothing lies inside the rectangle from
  /// (free_x0, free_y0) to (free_x1, free_y1) (the middle of the picture).
  double free_x0 = 0.0, free_y0 = 0.0, free_x1 = 0.0, free_y1 = 0.0;

  static HudLayout for_size(int width_px, int height_px);
};

class HudOverlay {
 public:
  /// Adds the display's actors to `renderer` (drawn after its 3D actors).
  void attach(vtkRenderer* renderer);
  /// Shows `state` in a picture of the given size.
  void draw(const HudState& state, int width_px, int height_px);
  void set_visible(bool visible);

  /// The text actors (for tests: each one's text and where it is drawn).
  [[nodiscard]] std::vector<vtkTextActor*> texts() const;
  /// The bars' polygons, in display pixels.
  [[nodiscard]] vtkPolyData* bars() const { return bars_; }

 private:
  vtkSmartPointer<vtkTextActor> text(double size_px, bool bold);
  void place_gauges(const HudState& state, const HudLayout& l, int width_px);

  vtkRenderer* renderer_ = nullptr;
  vtkSmartPointer<vtkActor2D> vignette_;
  vtkSmartPointer<vtkPolyData> vignette_poly_;
  vtkSmartPointer<vtkActor2D> bars_actor_;
  vtkSmartPointer<vtkPolyData> bars_;
  vtkSmartPointer<vtkUnsignedCharArray> bar_colours_;
  vtkSmartPointer<vtkTextActor> step_, instruction_, progress_, timer_, scope_, result_, loops_;
  std::array<vtkSmartPointer<vtkTextActor>, 2> gauge_labels_;
  std::array<vtkSmartPointer<vtkTextActor>, 2> squeeze_labels_;
  std::array<vtkSmartPointer<vtkTextActor>, HudModel::kMaxNotices> notices_;
  int width_ = 0;
  int height_ = 0;
};

}  // namespace lap::app
