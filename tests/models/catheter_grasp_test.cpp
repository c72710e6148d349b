// Grasping the catheter (§7.6.2–7.6.3): a grasped catheter follows the jaws, opening releases
// it, the squeeze grows with closure, and the haptic-rate coupling matches the model's springs.

#include "models/catheter_grasp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace lap::models {
namespace {

struct Scene {
  CatheterModel model = CatheterModel::build({});
  CatheterState cath{model, Eigen::Vector3d(-31 * model.rest_length_m(), 0.0, 0.0),
                     Eigen::Vector3d::UnitX()};  // particle 31 at the origin
  GraspSettings settings;
  GraspState grasp;
  JawFrame jaws;
  Scene() {
    jaws.hinge_W = Eigen::Vector3d(0.0, 0.01, 0.0);  // 1 cm above, jaws pointing down (−y)
    jaws.opening_rad = 0.8;
  }
  GraspOutput step() {
    const GraspOutput out = update_grasp(settings, jaws, model, &cath, &grasp);
    EXPECT_TRUE(step_catheter(model, &cath, 0.005));
    return out;
  }
};

TEST(CatheterGrasp, GraspedCatheterFollowsTheJawsAndOpeningReleasesIt) {
  Scene s;
  // Close: nothing is grasped above the grasp angle, then the particle between the jaws is.
  bool grasped = false;
  for (int k = 0; k <= 60; ++k) {
    s.jaws.opening_rad = 0.8 - 0.01 * k;
    const GraspOutput out = s.step();
    if (s.jaws.opening_rad >= s.settings.grasp_below_rad) {
      EXPECT_FALSE(s.grasp.grasping());
    }
    grasped = grasped || out.grasped_now;
  }
  ASSERT_TRUE(grasped);
  ASSERT_EQ(s.grasp.count, 1);
  EXPECT_EQ(s.grasp.particle[0], 31);
  // Lift the tool 2 cm along z over one second: the grasped particle follows.
  for (int k = 1; k <= 200; ++k) {
    s.jaws.hinge_W.z() = 0.02 * k / 200.0;
    s.step();
  }
  for (int k = 0; k < 100; ++k) s.step();  // settle
  const Eigen::Vector3d held = s.cath.positions[31];
  EXPECT_NEAR(held.z(), 0.02, 1e-3);
  std::printf("[ grasp ] tool lifted 20 mm: grasped particle at %.3f mm (%.3f mm off the jaws)\n",
              1e3 * held.z(),
              1e3 * (held - (s.jaws.hinge_W + Eigen::Vector3d(0.0, -0.01, 0.0))).norm());
  EXPECT_NEAR(held.y(), 0.0, 1e-3);
  // Its neighbours came along too (the chain), less and less towards the free ends.
  EXPECT_GT(s.cath.positions[35].z(), 0.01);
  // Open: released at once; moving the tool away no longer moves the catheter.
  s.jaws.opening_rad = 0.6;
  const GraspOutput open = s.step();
  EXPECT_TRUE(open.released_now);
  EXPECT_FALSE(s.grasp.grasping());
  EXPECT_EQ(open.force_on_tool_W.norm(), 0.0);
  for (int k = 1; k <= 200; ++k) {
    s.jaws.hinge_W.z() = 0.02 + 0.02 * k / 200.0;
    s.step();
  }
  EXPECT_LT(std::abs(s.cath.positions[31].z() - held.z()), 2e-3);
}

TEST(CatheterGrasp, SqueezeGrowsWithClosure) {
  Scene s;
  double last = 0.0;
  double first = -1.0;
  for (int k = 0; k <= 80; ++k) {
    s.jaws.opening_rad = 0.29 - 0.0034 * k;
    const GraspOutput out = s.step();
    EXPECT_GE(out.squeeze_n, last - 1e-12) << s.jaws.opening_rad;
    if (out.squeeze_n > 0.0 && first < 0.0) first = s.jaws.opening_rad;
    last = out.squeeze_n;
  }
  // Contact where the jaws' gap at 1 cm equals the 2.5 mm diameter: 2 asin(0.125) = 0.2507 rad.
  EXPECT_NEAR(first, 2.0 * std::asin(0.125), 0.004);
  EXPECT_GT(last, 1.0);
}

TEST(CatheterGrasp, HapticRateCouplingMatchesTheModelSprings) {
  Scene s;
  s.jaws.opening_rad = 0.2;
  s.step();
  ASSERT_TRUE(s.grasp.grasping());
  for (int k = 0; k < 50; ++k) s.step();
  // Between model steps the tool moves on: the coupling follows it smoothly and stays bounded.
  Eigen::Vector3d last = coupling_force(s.settings, s.jaws, s.cath, s.grasp);
  for (int tick = 1; tick <= 5; ++tick) {
    JawFrame now = s.jaws;
    now.hinge_W.x() += 0.0002 * tick;  // 0.2 mm per 1 ms tick
    const Eigen::Vector3d f = coupling_force(s.settings, now, s.cath, s.grasp);
    EXPECT_LE((f - last).norm(), s.settings.attach_stiffness_n_per_m * 0.0002 * 1.0001);
    EXPECT_LE(f.norm(), s.settings.max_force_n * s.grasp.count);
    // Pulled along +x, the tool is pulled back.
    EXPECT_LT(f.x(), 0.0);
    last = f;
  }
}

}  // namespace
}  // namespace lap::models
