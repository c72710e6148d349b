#include "app/laparoscope_camera.h"

#include <vtkCamera.h>

#include <algorithm>

namespace lap::app {
namespace {
constexpr double kFillIntensity = 0.12;  // the abdomen's scattered light (estimate, by eye)
}  // namespace

void LaparoscopeCamera::attach(vtkRenderer* renderer, double reference_distance_m) {
  renderer_ = renderer;
  renderer->RemoveAllLights();
  renderer->AutomaticLightCreationOff();
  tip_light_ = vtkSmartPointer<vtkLight>::New();
  tip_light_->SetLightTypeToSceneLight();
  tip_light_->SetPositional(true);
  // The fibres round the objective light a cone of about 100 degrees, brightest on the axis
  // (estimate; a laparoscope's light field is wider than its 70-80 degree view).
  tip_light_->SetConeAngle(55.0);
  tip_light_->SetExponent(2.0);
  tip_light_->SetColor(1.0, 0.97, 0.92);  // xenon/LED light through the fibres: near white
  // Brightness 1 / (c + q d^2), 1 at the reference distance: mostly the inverse square, with a
  // constant part standing in for the camera's automatic gain (estimate).
  const double d = std::max(reference_distance_m, 0.01);
  tip_light_->SetAttenuationValues(0.3, 0.0, 0.7 / (d * d));
  tip_light_->SetIntensity(1.0);
  renderer->AddLight(tip_light_);
  fill_light_ = vtkSmartPointer<vtkLight>::New();
  fill_light_->SetLightTypeToHeadlight();
  fill_light_->SetIntensity(kFillIntensity);
  fill_light_->SetColor(1.0, 0.85, 0.8);  // scattered off red tissue
  renderer->AddLight(fill_light_);
}

void LaparoscopeCamera::set_spot_light(bool on) {
  if (!tip_light_ || !fill_light_) return;
  // One light at the camera instead of two, one of them a spot: the shading's work per pixel
  // on a software renderer measured 10 % less (docs/benchmarks.md). The light keeps the
  // direction the scope's fibres light from (they are at the camera, nearly) and the fill's
  // share of the brightness, but not the fall-off with distance nor the cone.
  fill_light_->SetSwitch(on);
  if (on) {
    tip_light_->SetLightTypeToSceneLight();
    tip_light_->SetPositional(true);
  } else {
    tip_light_->SetLightTypeToHeadlight();
    tip_light_->SetPositional(false);
  }
  tip_light_->SetIntensity(on ? 1.0 : 1.0 + kFillIntensity);
}

void LaparoscopeCamera::apply(const sim::LaparoscopeView& view) {
  if (renderer_ == nullptr) return;
  vtkCamera* cam = renderer_->GetActiveCamera();
  cam->SetPosition(view.eye_W.x(), view.eye_W.y(), view.eye_W.z());
  cam->SetFocalPoint(view.focal_point_W.x(), view.focal_point_W.y(), view.focal_point_W.z());
  cam->SetViewUp(view.up_W.x(), view.up_W.y(), view.up_W.z());
  cam->SetViewAngle(view.view_angle_deg);
  // Near at 2 mm (the objective's own clearance), far beyond anything in the abdomen.
  cam->SetClippingRange(0.002, 0.8);
  tip_light_->SetPosition(view.light_W.x(), view.light_W.y(), view.light_W.z());
  tip_light_->SetFocalPoint(view.focal_point_W.x(), view.focal_point_W.y(), view.focal_point_W.z());
}

}  // namespace lap::app
