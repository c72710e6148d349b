// The laparoscope's kinematics (sim/runtime/laparoscope.h) against poses worked out by hand, and
// the camera assistant (sim/runtime/camera_assistant.h) against what an assistant must do: leave
// a centred working point alone, bring an off-centre one back smoothly, keep both tips in view.

#include "sim/runtime/laparoscope.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/runtime/camera_assistant.h"

namespace lap::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A scope through a port at z = 0.1 pointing down −z, 5 cm in, world up +y.
LaparoscopeModel scope(double optics_deg) {
  LaparoscopeModel m;
  m.port_W = Eigen::Vector3d(0.0, 0.0, 0.1);
  m.optic_angle_rad = optics_deg * kDeg;
  m.horizon_up_W = Eigen::Vector3d::UnitY();
  m.focal_distance_m = 0.1;
  m.home.axis_W = -Eigen::Vector3d::UnitZ();
  m.home.insertion_m = 0.05;
  m.home.view_angle_deg = 30.0;
  m.min_insertion_m = 0.01;
  m.max_insertion_m = 0.08;
  return m;
}

void expect_near(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tol = 1e-12) {
  EXPECT_LT((got - want).norm(), tol) << "got " << got.transpose() << ", want " << want.transpose();
}

// 0°: the eye 5 cm in from the port, looking along the axis, the world's up as the picture's.
TEST(Laparoscope, AForwardViewingScopeLooksAlongItsAxis) {
  const LaparoscopeModel m = scope(0.0);
  const LaparoscopeView v = laparoscope_view(m, m.home);
  expect_near(v.eye_W, Eigen::Vector3d(0.0, 0.0, 0.05));
  expect_near(v.view_dir_W, Eigen::Vector3d(0.0, 0.0, -1.0));
  expect_near(v.up_W, Eigen::Vector3d(0.0, 1.0, 0.0));
  expect_near(v.focal_point_W, Eigen::Vector3d(0.0, 0.0, -0.05));
  expect_near(v.light_W, v.eye_W);
  // Turning a 0° scope about its axis changes nothing the camera head shows...
  LaparoscopeState rolled = m.home;
  roll_laparoscope(&rolled, 40.0 * kDeg);
  expect_near(laparoscope_view(m, rolled).view_dir_W, v.view_dir_W);
  expect_near(laparoscope_view(m, rolled).up_W, v.up_W);
  // ...turning the camera head by 90° (about −z) puts +x up.
  LaparoscopeState turned = m.home;
  turn_laparoscope_horizon(&turned, 90.0 * kDeg);
  expect_near(laparoscope_view(m, turned).up_W, Eigen::Vector3d(1.0, 0.0, 0.0));
}

// 30°: r0 = +y (the world's up across the axis), so at roll 0 the line of sight is
// cos 30 (−z) + sin 30 (+y) = (0, 0.5, −0.866), and the level up is y made perpendicular to
// it: (0, 1, 0) − 0.5 (0, 0.5, −0.866) = (0, 0.75, 0.433), normalised (0, 0.866, 0.5).
// At roll 90°: s0 = axis × r0 = (−z) × y = +x, the line of sight (0.5, 0, −0.866), up +y.
TEST(Laparoscope, AnAngledOpticsViewTurnsWithTheScope) {
  const LaparoscopeModel m = scope(30.0);
  const double c = std::sqrt(3.0) / 2.0;
  LaparoscopeView v = laparoscope_view(m, m.home);
  expect_near(v.view_dir_W, Eigen::Vector3d(0.0, 0.5, -c));
  expect_near(v.up_W, Eigen::Vector3d(0.0, c, 0.5));
  expect_near(v.eye_W, Eigen::Vector3d(0.0, 0.0, 0.05));
  LaparoscopeState s = m.home;
  roll_laparoscope(&s, 90.0 * kDeg);
  v = laparoscope_view(m, s);
  expect_near(v.view_dir_W, Eigen::Vector3d(0.5, 0.0, -c));
  expect_near(v.up_W, Eigen::Vector3d(0.0, 1.0, 0.0));
  // Half a turn: looking down, (0, −0.5, −0.866); rolls wrap into (−π, π].
  roll_laparoscope(&s, 90.0 * kDeg);
  expect_near(laparoscope_view(m, s).view_dir_W, Eigen::Vector3d(0.0, -0.5, -c));
  roll_laparoscope(&s, 90.0 * kDeg);
  EXPECT_NEAR(s.roll_rad, -90.0 * kDeg, 1e-12);
}

// Pivoting about the port: 10° to the right swings a 0° view from −z towards +x (the picture's
// right: view × up = (−z) × y = +x), the eye round the port; then 10° up.
TEST(Laparoscope, PivotsAboutItsPortSlidesAndZoomsWithinItsLimits) {
  const LaparoscopeModel m = scope(0.0);
  LaparoscopeState s = m.home;
  pivot_laparoscope(m, &s, 10.0 * kDeg, 0.0);
  const Eigen::Vector3d right(std::sin(10.0 * kDeg), 0.0, -std::cos(10.0 * kDeg));
  expect_near(laparoscope_view(m, s).view_dir_W, right);
  expect_near(laparoscope_view(m, s).eye_W, m.port_W + 0.05 * right);
  s = m.home;
  pivot_laparoscope(m, &s, 0.0, 10.0 * kDeg);
  expect_near(laparoscope_view(m, s).view_dir_W,
              Eigen::Vector3d(0.0, std::sin(10.0 * kDeg), -std::cos(10.0 * kDeg)));
  // At most 60° from where it started.
  s = m.home;
  pivot_laparoscope(m, &s, 80.0 * kDeg, 0.0);
  EXPECT_NEAR(std::acos(s.axis_W.dot(m.home.axis_W)), 60.0 * kDeg, 1e-9);
  // In and out, within 1 and 8 cm.
  s = m.home;
  insert_laparoscope(m, &s, 0.02);
  EXPECT_NEAR(s.insertion_m, 0.07, 1e-15);
  expect_near(laparoscope_view(m, s).eye_W, Eigen::Vector3d(0.0, 0.0, 0.03));
  insert_laparoscope(m, &s, 1.0);
  EXPECT_EQ(s.insertion_m, 0.08);
  insert_laparoscope(m, &s, -1.0);
  EXPECT_EQ(s.insertion_m, 0.01);
  // Zoom 2x: tan(half angle) halves: 2 atan(tan 15° / 2) = 15.25°.
  s = m.home;
  zoom_laparoscope(m, &s, 2.0);
  EXPECT_NEAR(s.view_angle_deg, 2.0 * std::atan(std::tan(15.0 * kDeg) / 2.0) / kDeg, 1e-12);
  zoom_laparoscope(m, &s, 100.0);
  EXPECT_EQ(s.view_angle_deg, m.min_view_angle_deg);
  zoom_laparoscope(m, &s, 0.001);
  EXPECT_EQ(s.view_angle_deg, m.max_view_angle_deg);
}

// From a scenario's camera: without a port the scope sits 12 mm behind the camera's position on
// its line of sight, so a 0° scope shows exactly the scenario's view; with a port off that line
// and a 30° optic, the scope is aimed so that its line of sight passes through the focal point,
// 30° off its axis, the tip at the position's distance from the port.
TEST(Laparoscope, BuiltFromTheScenariosCameraItShowsTheScenariosView) {
  CameraSpec c;
  c.position_m = Eigen::Vector3d(0.03, -0.02, 0.26);
  c.focal_point_m = Eigen::Vector3d(-0.0126, 0.02, -0.0191);
  c.view_angle_deg = 35.0;
  Result<LaparoscopeModel> plain = LaparoscopeModel::build(c);
  ASSERT_TRUE(plain.ok()) << plain.message();
  const LaparoscopeView v = laparoscope_view(plain.value(), plain.value().home);
  expect_near(v.eye_W, c.position_m, 1e-12);
  expect_near(v.view_dir_W, (c.focal_point_m - c.position_m).normalized(), 1e-12);
  EXPECT_NEAR(plain.value().focal_distance_m, (c.focal_point_m - c.position_m).norm(), 1e-12);
  EXPECT_EQ(v.view_angle_deg, 35.0);

  c.port_m = Eigen::Vector3d(0.03, -0.02, 0.272);  // the umbilical port
  c.optics_deg = 30.0;
  Result<LaparoscopeModel> angled = LaparoscopeModel::build(c);
  ASSERT_TRUE(angled.ok()) << angled.message();
  const LaparoscopeModel& m = angled.value();
  const LaparoscopeView a = laparoscope_view(m, m.home);
  EXPECT_LT(laparoscope_off_axis_rad(a, c.focal_point_m), 1e-6);
  EXPECT_NEAR(std::acos(a.view_dir_W.dot(m.home.axis_W)), 30.0 * kDeg, 1e-9);
  EXPECT_NEAR((a.eye_W - *c.port_m).norm(), 0.012, 1e-12);
  EXPECT_NEAR((a.eye_W - *c.port_m).normalized().dot(m.home.axis_W), 1.0, 1e-12);

  // The focal point within the scope's reach of its port cannot be looked at.
  c.focal_point_m = *c.port_m + Eigen::Vector3d(0.0, 0.0, -0.015);
  const Result<LaparoscopeModel> bad = LaparoscopeModel::build(c, "s.yaml");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("camera.focal_point_m"), std::string::npos) << bad.message();
}

// Aiming converges (the scope pivots at its port, so the eye moves with the axis and each step
// leaves a smaller angle than the last), for 0° and 30° optics alike.
TEST(Laparoscope, AimingPutsATargetOnTheLineOfSight) {
  for (const double optics : {0.0, 30.0}) {
    const LaparoscopeModel m = scope(optics);
    LaparoscopeState s = m.home;
    const Eigen::Vector3d target(0.03, -0.02, -0.06);
    double left = laparoscope_off_axis_rad(laparoscope_view(m, s), target);
    for (int k = 0; k < 100 && left > 1e-10; ++k) {
      const double next = aim_laparoscope(m, &s, target, 1.0);
      EXPECT_LT(next, left) << optics << " step " << k;
      left = next;
    }
    EXPECT_LT(left, 1e-10) << optics;
    EXPECT_NEAR(s.axis_W.norm(), 1.0, 1e-12);
  }
}

// Tips a few millimetres either side of the line of sight, 7 cm ahead: inside the dead zone and
// within the band of spreads: the assistant does not move the scope.
TEST(CameraAssistant, LeavesACentredWorkingPointAlone) {
  const LaparoscopeModel m = scope(0.0);
  LaparoscopeState s = m.home;
  CameraAssistant assistant;
  const std::array<Eigen::Vector3d, 2> tips = {Eigen::Vector3d(-0.008, 0.001, -0.02),
                                               Eigen::Vector3d(0.008, 0.001, -0.02)};
  for (int k = 0; k < 120; ++k) assistant.step(m, &s, tips, 1.0 / 60.0);
  expect_near(s.axis_W, m.home.axis_W);
  EXPECT_EQ(s.insertion_m, m.home.insertion_m);
}

// The working point 12° off the line of sight (beyond the dead zone, 0.2 × 15°): the view
// closes on it as a first-order lag — each step turns the scope by the share 1 − exp(−dt/τ) of
// the angle left (smooth, no jump) — and within 2 s the point is back inside the dead zone,
// where it stops.
TEST(CameraAssistant, BringsAnOffCentreWorkingPointBackSmoothly) {
  const LaparoscopeModel m = scope(0.0);
  LaparoscopeState s = m.home;
  CameraAssistant assistant;
  const Eigen::Vector3d eye = laparoscope_view(m, s).eye_W;
  const double distance = 0.07;
  const Eigen::Vector3d work =
      eye + distance * Eigen::Vector3d(std::sin(12.0 * kDeg), 0.0, -std::cos(12.0 * kDeg));
  // The two tips 1.5 cm apart across the working point: a spread within the band.
  const std::array<Eigen::Vector3d, 2> tips = {work + Eigen::Vector3d(0.0, 0.0075, 0.0),
                                               work - Eigen::Vector3d(0.0, 0.0075, 0.0)};
  const double dt = 1.0 / 60.0;
  const double share = 1.0 - std::exp(-dt / assistant.settings().time_constant_s);
  double off = laparoscope_off_axis_rad(laparoscope_view(m, s), work);
  EXPECT_NEAR(off, 12.0 * kDeg, 0.2 * kDeg);
  for (int k = 0; k < 120; ++k) {
    const Eigen::Vector3d before = laparoscope_view(m, s).view_dir_W;
    const bool following = assistant.step(m, &s, tips, dt);
    const Eigen::Vector3d after = laparoscope_view(m, s).view_dir_W;
    const double turn = std::acos(std::clamp(before.dot(after), -1.0, 1.0));
    EXPECT_LE(turn, share * off + 1e-9) << "step " << k << ": a jump";
    const double now = laparoscope_off_axis_rad(laparoscope_view(m, s), work);
    EXPECT_LE(now, off + 1e-12) << "step " << k << ": moved away";
    if (following) {
      EXPECT_GT(turn, 0.5 * share * off) << "step " << k << ": stalled";
    }
    off = now;
  }
  const double half_view = 0.5 * m.home.view_angle_deg * kDeg;
  EXPECT_LT(off, assistant.settings().dead_zone * half_view);
  EXPECT_FALSE(assistant.following());
}

// Tips spread wide (30° apart, beyond `widest` of the half view): the scope withdraws until
// both are well inside the picture; tips close together: it goes in (not nearer than 4 cm).
TEST(CameraAssistant, KeepsBothTipsInView) {
  const LaparoscopeModel m = scope(0.0);
  CameraAssistant assistant;
  const double half_view = 0.5 * m.home.view_angle_deg * kDeg;
  // (Both cases keep the working point on the line of sight: the spread is the tips' angle.)
  auto spread = [](const LaparoscopeView& v, const std::array<Eigen::Vector3d, 2>& tips) {
    return std::max(laparoscope_off_axis_rad(v, tips[0]), laparoscope_off_axis_rad(v, tips[1]));
  };
  LaparoscopeState s = m.home;
  const std::array<Eigen::Vector3d, 2> wide = {Eigen::Vector3d(-0.01, 0.0, 0.0),
                                               Eigen::Vector3d(0.01, 0.0, 0.0)};
  EXPECT_GT(spread(laparoscope_view(m, s), wide), assistant.settings().widest * half_view);
  for (int k = 0; k < 300; ++k) assistant.step(m, &s, wide, 1.0 / 60.0);
  EXPECT_LT(s.insertion_m, m.home.insertion_m);
  EXPECT_LE(spread(laparoscope_view(m, s), wide), assistant.settings().widest * half_view + 1e-3);

  s = m.home;
  const std::array<Eigen::Vector3d, 2> close = {Eigen::Vector3d(-0.001, 0.0, -0.05),
                                                Eigen::Vector3d(0.001, 0.0, -0.05)};
  for (int k = 0; k < 300; ++k) assistant.step(m, &s, close, 1.0 / 60.0);
  EXPECT_GT(s.insertion_m, m.home.insertion_m);
  EXPECT_GE((laparoscope_view(m, s).eye_W - Eigen::Vector3d(0.0, 0.0, -0.05)).norm(),
            assistant.settings().min_distance_m - 1e-6);
}

}  // namespace
}  // namespace lap::sim
