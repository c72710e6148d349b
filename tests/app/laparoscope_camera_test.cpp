// The laparoscope as VTK draws it (app/laparoscope_camera.h): the camera at the scope's objective,
// at its tip (the port plus the insertion along the axis), looking along the optic's line of
// sight (30 degrees off the axis for an angled scope); the scope's light at the same tip, a
// positional spot aimed along the line of sight whose brightness is 1 at the working distance
// and falls with distance; a faint fill. The fast profile keeps one light at the camera.

#include "app/laparoscope_camera.h"

#include <gtest/gtest.h>
#include <vtkCamera.h>
#include <vtkLight.h>
#include <vtkLightCollection.h>
#include <vtkNew.h>
#include <vtkRenderer.h>

#include <cmath>

namespace lap::app {
namespace {

Eigen::Vector3d v3(const double* p) { return {p[0], p[1], p[2]}; }

TEST(LaparoscopeCamera, TheCameraAndTheLightAreAtTheScopesTipAlongItsLineOfSight) {
  sim::LaparoscopeModel model;
  model.port_W = Eigen::Vector3d(0.0, 0.1, 0.25);
  model.optic_angle_rad = M_PI / 6.0;  // a 30-degree scope
  model.focal_distance_m = 0.08;
  sim::LaparoscopeState state;
  state.axis_W = Eigen::Vector3d(0.0, -0.6, -0.8);
  state.insertion_m = 0.07;
  state.view_angle_deg = 40.0;
  const sim::LaparoscopeView view = sim::laparoscope_view(model, state);
  const Eigen::Vector3d tip = model.port_W + 0.07 * state.axis_W;  // 7 cm in along the axis
  ASSERT_LT((view.eye_W - tip).norm(), 1e-12);
  // The angled optic looks 30 degrees off the scope's axis.
  EXPECT_NEAR(std::acos(view.view_dir_W.dot(state.axis_W)), M_PI / 6.0, 1e-9);

  vtkNew<vtkRenderer> renderer;
  LaparoscopeCamera camera;
  camera.attach(renderer, 0.08);
  camera.apply(view);
  vtkCamera* c = renderer->GetActiveCamera();
  EXPECT_LT((v3(c->GetPosition()) - tip).norm(), 1e-12);
  const Eigen::Vector3d sight = (v3(c->GetFocalPoint()) - v3(c->GetPosition())).normalized();
  EXPECT_LT((sight - view.view_dir_W).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(c->GetViewAngle(), 40.0);

  ASSERT_EQ(renderer->GetLights()->GetNumberOfItems(), 2);
  vtkLight* light = camera.tip_light();
  ASSERT_NE(light, nullptr);
  EXPECT_TRUE(light->GetPositional());
  EXPECT_TRUE(light->LightTypeIsSceneLight());
  EXPECT_LT((v3(light->GetPosition()) - tip).norm(), 1e-12);
  const Eigen::Vector3d aim = (v3(light->GetFocalPoint()) - v3(light->GetPosition())).normalized();
  EXPECT_LT((aim - view.view_dir_W).norm(), 1e-12);
  // Brightness 1 / (c + q d^2): 1 at the 8 cm working distance, under half of it at twice that
  // distance, over 1.5 times it at half.
  const double* att = light->GetAttenuationValues();
  auto brightness = [&](double d) { return 1.0 / (att[0] + att[1] * d + att[2] * d * d); };
  EXPECT_NEAR(brightness(0.08), 1.0, 1e-12);
  EXPECT_LT(brightness(0.16), 0.5);
  EXPECT_GT(brightness(0.04), 1.5);

  // The fast profile: one light at the camera (a headlight), the fill's share added to it.
  const double spot = light->GetIntensity();
  camera.set_spot_light(false);
  EXPECT_TRUE(light->LightTypeIsHeadlight());
  EXPECT_GT(light->GetIntensity(), spot);  // the fill's share added to it
  int on = 0;
  renderer->GetLights()->InitTraversal();
  while (vtkLight* l = renderer->GetLights()->GetNextItem()) on += l->GetSwitch() ? 1 : 0;
  EXPECT_EQ(on, 1);
  camera.set_spot_light(true);
  EXPECT_TRUE(light->LightTypeIsSceneLight());
  EXPECT_TRUE(light->GetPositional());
}

}  // namespace
}  // namespace lap::app
