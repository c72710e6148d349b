#pragma once
/// \file
/// The laparoscope's view as VTK draws it (sim/runtime/laparoscope.h computes the scope's pose):
/// the renderer's camera at the scope's objective looking along its line of sight, and the
/// scope's light at its tip — a positional spot light whose brightness falls with distance, as
/// a light carried into the abdomen does (so what the tip nears glares and the far field
/// darkens), rather than a light at infinity. A faint fill keeps unlit sides from going black,
/// as the light scattered in the abdomen does.

#include <vtkLight.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include "sim/runtime/laparoscope.h"

namespace lap::app {

class LaparoscopeCamera {
 public:
  /// Puts the tip light and the fill into `renderer` (its other lights removed); the light's
  /// brightness is 1 at `reference_distance_m` from the tip (the scope's working distance).
  void attach(vtkRenderer* renderer, double reference_distance_m);
  /// The camera and the light at the view.
  void apply(const sim::LaparoscopeView& view);
  /// The tip light as a positional spot whose brightness falls with distance, and the fill
  /// (true, the default), or one light at the camera with the fill's share (the renderer's
  /// fast profile: render_quality.h).
  void set_spot_light(bool on);

  [[nodiscard]] vtkLight* tip_light() const { return tip_light_; }

 private:
  vtkRenderer* renderer_ = nullptr;
  vtkSmartPointer<vtkLight> tip_light_;
  vtkSmartPointer<vtkLight> fill_light_;
};

}  // namespace lap::app
