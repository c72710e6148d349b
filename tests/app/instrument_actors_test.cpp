// Where an instrument is drawn (app/instrument_actors.h): at the device's pose while it touches
// nothing; pushed out of the tissue, rigidly and through its port, by the largest displacement
// of its proxies (plus the part's half-thickness along the contact's normal) when it presses an
// organ; each jaw at its proxy's angle. The actors' matrices put the shapes there.

#include "app/instrument_actors.h"

#include <gtest/gtest.h>
#include <vtkNew.h>

#include <cmath>

namespace lap::app {
namespace {

struct Fixture {
  InstrumentSpec spec;
  sim::ToolSnapshot tool;
  std::array<Eigen::Vector3d, 3> a;
  std::array<Eigen::Vector3d, 3> b;
  Fixture() {
    spec.shaft_radius_m = 0.0025;
    spec.gripper.shaft_length_m = 0.36;
    spec.gripper.jaw_length_m = 0.02;
    tool.pose.hinge_W = Eigen::Vector3d(0.0, 0.0, 0.0);
    tool.pose.shaft_dir_W = Eigen::Vector3d(0.0, 0.6, 0.8);  // towards the handle
    tool.pose.open_dir_W = Eigen::Vector3d(1.0, 0.0, 0.0);
    tool.pose.opening_rad = 0.6;
    spec.port_W = 0.2 * tool.pose.shaft_dir_W;  // the shaft passes its port 20 cm up
    haptics::LaparoscopicGripper(spec.gripper).segments(tool.pose, &a, &b);
    tool.proxy_a_W = a;  // free: the proxies are where the device puts the segments
    tool.proxy_b_W = b;
  }
};

void expect_near(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tol = 1e-12) {
  EXPECT_LT((got - want).norm(), tol) << got.transpose() << " vs " << want.transpose();
}

TEST(InstrumentPose, AFreeInstrumentIsWhereTheDevicePutsIt) {
  const Fixture f;
  const InstrumentPose p = drawn_instrument_pose(f.spec, f.tool);
  expect_near(p.hinge_W, f.tool.pose.hinge_W);
  expect_near(p.shaft_dir_W, f.tool.pose.shaft_dir_W);
  expect_near(p.open_dir_W, f.tool.pose.open_dir_W);
  // Jaw tips as the gripper's segments have them (their a ends).
  expect_near(p.jaw_tip_W[0], f.a[1]);
  expect_near(p.jaw_tip_W[1], f.a[2]);
}

// Jaw 0's proxy held 3 mm up (+y) by the liver below it, its contact normal +y: the whole
// instrument is drawn 3 mm + 0.8 x 2.5 mm = 5 mm up, its shaft turned to keep through the port,
// jaw 0 at its proxy's angle (the same here: the proxy moved without turning).
TEST(InstrumentPose, AnInstrumentPressingAnOrganIsDrawnOnItsSurface) {
  Fixture f;
  const Eigen::Vector3d up(0.0, 1.0, 0.0);
  f.tool.proxy_a_W[1] += 0.003 * up;
  f.tool.proxy_b_W[1] += 0.003 * up;
  f.tool.proxy_normal_W[1] = up;
  const InstrumentPose p = drawn_instrument_pose(f.spec, f.tool);
  expect_near(p.hinge_W, f.tool.pose.hinge_W + 0.005 * up);
  expect_near(p.shaft_dir_W, (f.spec.port_W - p.hinge_W).normalized());
  EXPECT_NEAR(p.shaft_dir_W.norm(), 1.0, 1e-12);
  EXPECT_NEAR(p.open_dir_W.dot(p.shaft_dir_W), 0.0, 1e-12);
  // The jaw's half-opening: its proxy's (0.3 rad from the device's shaft), now about the drawn
  // shaft; the drawn jaw tip at least as high as the proxy's.
  EXPECT_NEAR(std::acos(p.jaw_dir_W[0].dot(-p.shaft_dir_W)), 0.3, 1e-9);
  EXPECT_GE(p.jaw_tip_W[0].y(), f.tool.proxy_a_W[1].y() - 1e-4);
  // Jaw 1 pressed closed by tissue on its back: its proxy turned to 0.1 rad: drawn so.
  Fixture g;
  const Eigen::Vector3d u = g.tool.pose.shaft_dir_W;
  const Eigen::Vector3d o = g.tool.pose.open_dir_W;
  g.tool.proxy_a_W[2] = g.b[2] + 0.02 * (std::cos(0.1) * -u - std::sin(0.1) * o);
  g.tool.proxy_normal_W[2] = -o;
  const InstrumentPose q = drawn_instrument_pose(g.spec, g.tool);
  EXPECT_NEAR(std::acos(q.jaw_dir_W[1].dot(-q.shaft_dir_W)), 0.1, 1e-6);
}

// A probe is drawn with its tip where its proxy holds it (on the surface the device's tip went
// into), its rod through its port, and no jaws.
TEST(InstrumentActors, AProbeIsDrawnAtItsProxysTipWithoutJaws) {
  Fixture f;
  f.spec.kind = InstrumentKind::kProbe;
  f.tool.kind = sim::ToolKind::kPointProbe;
  f.tool.proxy_tip_W = Eigen::Vector3d(0.0, 0.004, 0.0);  // held 4 mm above the device's tip
  const InstrumentPose p = drawn_instrument_pose(f.spec, f.tool);
  expect_near(p.hinge_W, f.tool.proxy_tip_W);
  expect_near(p.shaft_dir_W, (f.spec.port_W - f.tool.proxy_tip_W).normalized());
  vtkNew<vtkRenderer> renderer;
  InstrumentActors actors;
  actors.add(renderer, f.spec);
  actors.update(f.tool);
  EXPECT_TRUE(actors.shaft()->GetVisibility());
  EXPECT_FALSE(actors.jaw(0)->GetVisibility());
  EXPECT_FALSE(actors.jaw(1)->GetVisibility());
}

TEST(InstrumentActors, TheShapesArePlacedByTheirMatrices) {
  Fixture f;
  vtkNew<vtkRenderer> renderer;
  InstrumentActors actors;
  actors.add(renderer, f.spec);
  EXPECT_FALSE(actors.shaft()->GetVisibility());  // nothing to show before the first tick
  actors.update(f.tool);
  EXPECT_TRUE(actors.shaft()->GetVisibility());
  const InstrumentPose& p = actors.pose();
  for (int j = 0; j < 2; ++j) {
    double tip[4] = {0.0, -f.spec.gripper.jaw_length_m, 0.0, 1.0};
    double out[4];
    actors.jaw(j)->GetUserMatrix()->MultiplyPoint(tip, out);
    expect_near(Eigen::Vector3d(out[0], out[1], out[2]), p.jaw_tip_W[static_cast<size_t>(j)], 1e-9);
    // The jaw's back (+x in its frame) faces away from the other jaw.
    double back[4] = {0.001, -0.01, 0.0, 1.0};
    actors.jaw(j)->GetUserMatrix()->MultiplyPoint(back, out);
    const double side = j == 0 ? 1.0 : -1.0;
    double mid[4] = {0.0, -0.01, 0.0, 1.0};
    double on[4];
    actors.jaw(j)->GetUserMatrix()->MultiplyPoint(mid, on);
    EXPECT_GT(side * (out[0] - on[0]), 0.0);
  }
  double handle[4] = {0.0, 0.2, 0.0, 1.0};
  double out[4];
  actors.shaft()->GetUserMatrix()->MultiplyPoint(handle, out);
  expect_near(Eigen::Vector3d(out[0], out[1], out[2]), f.spec.port_W, 1e-9);
}

}  // namespace
}  // namespace lap::app
