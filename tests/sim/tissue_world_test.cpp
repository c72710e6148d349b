// The modelling loop's world on the introductory scene (issue 6): the duct's shell fitted to the
// scenario's duct, published deformations applied exactly by a reader that skips snapshots, a
// tool's push denting an organ by its share of the penetration, the duct pushed and grasped, and
// a fast session whose organs deform under the scripted tools.

#include "sim/runtime/tissue_world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <set>

#include "haptics/setup/mesh_generators.h"
#include "hardware/scripted_device.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/duct_fit.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

const Scene& introductory_scene() {
  static const SceneLoadResult r =
      load_scene_file(test::source_dir() / "scenarios/introductory.yaml");
  EXPECT_TRUE(r.ok());
  return r.value();
}

TEST(DuctFit, FitsTheStandInDuct) {
  const DuctFit f = fit_duct(haptics::make_stand_in_cystic_duct(), 0.001).value();
  EXPECT_NEAR(f.duct.outer_diameter_m, 0.005, 0.02 * 0.005);  // generated: 2.5 mm radius
  EXPECT_NEAR(f.duct.length_m, 0.035, 1e-6);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.85, -0.3, -0.45).normalized();
  EXPECT_NEAR(std::abs(f.pose_WD.linear().col(2).dot(axis)), 1.0, 1e-9);
  EXPECT_GT(f.pose_WD.linear().col(1).y(), 0.0);  // the membrane (local −y) faces down
  EXPECT_NEAR(f.pose_WD.linear().determinant(), 1.0, 1e-12);
  EXPECT_FALSE(fit_duct(haptics::make_stand_in_cystic_duct(), 0.003).ok());  // thicker than r
}

TEST(DeformedSurface, AReaderThatSkipsSnapshotsStillEndsExact) {
  std::vector<Eigen::Vector3d> rest(200);
  for (size_t v = 0; v < rest.size(); ++v) rest[v] = Eigen::Vector3d(0.001 * v, 0.0, 0.0);
  DeformedSurface reader(rest);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> vertex(0, 199);
  std::vector<Eigen::Vector3d> before = rest;
  for (int round = 0; round < 200; ++round) {
    SurfaceDeformation d(rest.size());
    std::vector<Eigen::Vector3d> expected = rest;
    d.count = round % 30;
    for (int32_t k = 0; k < d.count; ++k) {
      const int32_t v = vertex(rng);
      d.vertex[static_cast<size_t>(k)] = v;
      d.position[static_cast<size_t>(k)] =
          rest[static_cast<size_t>(v)] + Eigen::Vector3d(0, 1e-3 * k, 0);
      // A vertex listed twice keeps its first position.
      bool first = true;
      for (int32_t j = 0; j < k; ++j) first = first && d.vertex[static_cast<size_t>(j)] != v;
      if (first) expected[static_cast<size_t>(v)] = d.position[static_cast<size_t>(k)];
    }
    if (round % 7 == 0 && d.count > 0) d.vertex[0] = 1000;  // out of range: ignored
    if (round % 7 == 0 && d.count > 0)
      expected = [&] {
        std::vector<Eigen::Vector3d> e = rest;
        std::set<int32_t> seen;
        for (int32_t k = 1; k < d.count; ++k) {
          const int32_t v = d.vertex[static_cast<size_t>(k)];
          if (seen.insert(v).second) e[static_cast<size_t>(v)] = d.position[static_cast<size_t>(k)];
        }
        return e;
      }();
    const std::span<const int32_t> changed = reader.apply(d);
    const std::set<int32_t> listed(changed.begin(), changed.end());
    EXPECT_EQ(listed.size(), changed.size()) << "a vertex listed twice";
    for (size_t v = 0; v < rest.size(); ++v) {
      ASSERT_EQ(reader.positions()[v], expected[v]) << "round " << round << " vertex " << v;
      if (expected[v] != before[v]) {
        EXPECT_TRUE(listed.count(static_cast<int32_t>(v))) << "moved but not listed: " << v;
      }
    }
    before = expected;
  }
}

TissueWorldSettings world_settings(const std::filesystem::path& cache) {
  TissueWorldSettings s;
  s.catheter_start_W = Eigen::Vector3d(0.0, 0.2, 0.2);  // far from every organ
  s.catheter_direction_W = Eigen::Vector3d::UnitY();
  s.mode_cache_dir = cache;
  return s;
}

int32_t organ_named(const Scene& scene, const std::string& name) {
  for (size_t i = 0; i < scene.organs.size(); ++i) {
    if (scene.organs[i].name == name) return static_cast<int32_t>(i);
  }
  return -1;
}

// The introductory scene's tissue world, and its liver as a database at rest (the organ the tool
// tests press).
struct LiverWorld {
  test::TempDir cache;
  std::unique_ptr<TissueWorld> world;
  int32_t liver = -1;  // -1: the scene has none
  haptics::MeshDatabase db;
};

// `max_move_per_step_m`: the surface's speed limit (0: none, as world_settings leaves it).
std::unique_ptr<LiverWorld> liver_world(double max_move_per_step_m = 0.0) {
  auto w = std::make_unique<LiverWorld>();
  TissueWorldSettings s = world_settings(w->cache.path());
  s.local.max_move_per_step_m = max_move_per_step_m;
  w->world = TissueWorld::build(introductory_scene(), s, nullptr).value();
  w->liver = organ_named(introductory_scene(), "liver");
  if (w->liver >= 0) w->db = haptics::MeshDatabase::build(w->world->surface(w->liver));
  return w;
}

// One tool pushing `push_n` on the middle of the liver's face 100, along its inward normal.
std::array<ToolModelInput, 2> push_on_face_100(const LiverWorld& lw, double push_n) {
  std::array<ToolModelInput, 2> tools{};
  tools[0].valid = true;
  tools[0].jaws.opening_rad = 0.8;
  tools[0].contact_count = 1;
  ToolContact& c = tools[0].contacts[0];
  c.organ = lw.liver;
  c.primitive = {haptics::PrimitiveKind::kFace, 100};
  const auto& fv = lw.db.face_vertices(100);
  c.point_W = (lw.db.position(fv[0]) + lw.db.position(fv[1]) + lw.db.position(fv[2])) / 3.0;
  c.force_on_organ_W = -push_n * lw.db.face_normal(100);
  return tools;
}

TEST(TissueWorld, AToolsPushDentsTheLiverByItsShareOfThePenetration) {
  const Scene& scene = introductory_scene();
  const auto lw = liver_world();
  ASSERT_GE(lw->liver, 0);
  const auto& [cache, world, liver, db] = *lw;
  const haptics::TriangleMesh& surface = world->surface(liver);
  // A push 2 mm deep (by the liver's stiffness) on the middle of face 100, along its inward
  // normal.
  const double k = scene.organs[static_cast<size_t>(liver)].material.stiffness_n_per_m;
  const double push_n = 0.002 * k;
  std::array<ToolModelInput, 2> tools = push_on_face_100(*lw, push_n);
  const ToolContact& c = tools[0].contacts[0];
  for (int step = 0; step < 5; ++step) world->step(tools, 0.005);
  std::vector<SurfaceDeformation> d = world->make_deformations();
  world->write_deformations(&d);
  const SurfaceDeformation& dl = d[static_cast<size_t>(liver)];
  ASSERT_GT(dl.count, 0);
  // The deepest vertex moved share × F / k along the push (the contact's own point: weight ~1).
  const double expected = world->settings().local.surface_share * push_n / k;
  EXPECT_LE(world->deepest_dent_m(), expected * (1 + 1e-12));
  EXPECT_GT(world->deepest_dent_m(), 0.8 * expected);
  // Nothing beyond R moved; no other organ moved.
  for (int32_t i = 0; i < dl.count; ++i) {
    const int32_t v = dl.vertex[static_cast<size_t>(i)];
    EXPECT_LT((surface.positions[static_cast<size_t>(v)] - c.point_W).norm(),
              world->settings().local.radius_m + 1e-12);
  }
  for (size_t o = 0; o < d.size(); ++o) {
    if (static_cast<int32_t>(o) != liver) {
      EXPECT_EQ(d[o].count, 0) << scene.organs[o].name;
    }
  }
  // Released: back to rest.
  tools[0].contact_count = 0;
  world->step(tools, 0.005);
  world->write_deformations(&d);
  EXPECT_EQ(d[static_cast<size_t>(liver)].count, 0);
}

// A gripper's segment without a contact on the liver is an obstacle to its dent
// (models::DeformationObstacle); the segment that makes the contact is not. A push 2 mm deep (by
// the liver's stiffness) on face 100 dents it 1 mm (the share); halved, the dent rises to 0.5 mm
// past a segment of the same tool lying 0.75 mm down across it. Where the contact is that
// segment's own, the dent rises freely; where it is another segment's, the rising vertices
// stop short of it and the dent stays 1 mm deep.
TEST(TissueWorld, ADentRisesPastTheSegmentThatPressesItNotPastAnother) {
  const Scene& scene = introductory_scene();
  for (const int32_t pressing_segment : {0, 1}) {
    SCOPED_TRACE(pressing_segment == 0 ? "the segment's own contact" : "another segment's");
    const auto lw = liver_world();
    ASSERT_GE(lw->liver, 0);
    TissueWorld& world = *lw->world;
    const double liver_k = scene.organs[static_cast<size_t>(lw->liver)].material.stiffness_n_per_m;
    std::array<ToolModelInput, 2> tools = push_on_face_100(*lw, 0.002 * liver_k);
    ToolContact& c = tools[0].contacts[0];
    c.segment = pressing_segment;
    const Eigen::Vector3d n = lw->db.face_normal(100);
    const Eigen::Vector3d along = n.unitOrthogonal();
    const Eigen::Vector3d middle = c.point_W - 0.00075 * n;
    tools[0].has_proxies = true;
    tools[0].proxy_a_W[0] = middle - 0.005 * along;
    tools[0].proxy_b_W[0] = middle + 0.005 * along;
    const double share = world.settings().local.surface_share;
    for (int step = 0; step < 3; ++step) world.step(tools, 0.005);
    EXPECT_NEAR(world.deepest_dent_m(), share * 0.002, 0.1 * share * 0.002);
    c.force_on_organ_W *= 0.5;
    for (int step = 0; step < 3; ++step) world.step(tools, 0.005);
    if (pressing_segment == 0) {
      EXPECT_NEAR(world.deepest_dent_m(), share * 0.001, 0.1 * share * 0.001);
    } else {
      EXPECT_NEAR(world.deepest_dent_m(), share * 0.002, 0.1 * share * 0.002);
    }
  }
}

// An author's live stiffness (TissueWorld::set_stiffness): the same push on a liver tuned to half
// its stiffness implies twice the tool's displacement, so it dents twice as deep; a stiffness
// that is not finite and positive, or an organ that is not one, changes nothing.
TEST(TissueWorld, ATunedStiffnessScalesTheDentAToolsPushImplies) {
  const Scene& scene = introductory_scene();
  const auto lw = liver_world();
  ASSERT_GE(lw->liver, 0);
  TissueWorld* world = lw->world.get();  // a pointer, not a binding: lambdas capture it
  const int32_t liver = lw->liver;
  const double k = scene.organs[static_cast<size_t>(liver)].material.stiffness_n_per_m;
  EXPECT_EQ(world->stiffness_n_per_m(liver), k);
  EXPECT_FALSE(world->set_stiffness(liver, 0.0));
  EXPECT_FALSE(world->set_stiffness(liver, -k));
  EXPECT_FALSE(world->set_stiffness(liver, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(world->set_stiffness(world->organ_count(), k));
  EXPECT_FALSE(world->set_stiffness(-1, k));
  EXPECT_EQ(world->stiffness_n_per_m(liver), k);
  std::array<ToolModelInput, 2> tools = push_on_face_100(*lw, 0.001 * k);  // 1 mm at its k
  const auto dent_after_one_step = [&] {
    world->step(tools, 0.005);
    const double d = world->deepest_dent_m();
    tools[0].contact_count = 0;  // released: back to rest
    world->step(tools, 0.005);
    tools[0].contact_count = 1;
    return d;
  };
  const double at_k = dent_after_one_step();
  ASSERT_GT(at_k, 0.0);
  ASSERT_TRUE(world->set_stiffness(liver, 0.5 * k));
  EXPECT_EQ(world->stiffness_n_per_m(liver), 0.5 * k);
  EXPECT_NEAR(dent_after_one_step(), 2.0 * at_k, 1e-9 * at_k);
}

// A tool held 4 mm into the liver with its three segments on one spot, each pushing as the
// haptic loop would (stiffness times its depth below the surface the last step left). The dent
// settles between the rest surface and the tool and never passes it: passing it would leave the
// tool inside the organ with no force once the dent swings back. Summing the three pushes in
// full did that (the dent overshot to 1.3 times the tool's depth on the first step).
TEST(TissueWorld, ThreeSegmentsOnOneSpotDentItWithoutOvershootingTheTool) {
  const Scene& scene = introductory_scene();
  const auto lw = liver_world();
  ASSERT_GE(lw->liver, 0);
  const auto& [cache, world, liver, db] = *lw;
  const haptics::TriangleMesh& surface = world->surface(liver);
  const auto& fv = db.face_vertices(100);
  const Eigen::Vector3d p = (db.position(fv[0]) + db.position(fv[1]) + db.position(fv[2])) / 3.0;
  const Eigen::Vector3d n = db.face_normal(100);
  const double k = scene.organs[static_cast<size_t>(liver)].material.stiffness_n_per_m;
  const double tool_depth = 0.004;
  std::vector<Eigen::Vector3d> positions = surface.positions;
  std::vector<SurfaceDeformation> d = world->make_deformations();
  std::array<ToolModelInput, 2> tools{};
  tools[0].valid = true;
  tools[0].jaws.opening_rad = 0.8;
  tools[0].contact_count = 3;
  double dent = 0.0;
  double last_change = 1.0;
  for (int step = 0; step < 40; ++step) {
    const double depth = std::max(0.0, tool_depth - dent);  // below the dented surface
    for (int c = 0; c < 3; ++c) {
      ToolContact& tc = tools[0].contacts[static_cast<size_t>(c)];
      tc.organ = liver;
      tc.primitive = {haptics::PrimitiveKind::kFace, 100};
      tc.point_W = p - dent * n;
      tc.force_on_organ_W = -k * depth * n;
    }
    world->step(tools, 0.005);
    world->write_deformations(&d);
    positions = surface.positions;
    const SurfaceDeformation& dl = d[static_cast<size_t>(liver)];
    for (int32_t i = 0; i < dl.count; ++i) {
      positions[static_cast<size_t>(dl.vertex[static_cast<size_t>(i)])] =
          dl.position[static_cast<size_t>(i)];
    }
    const Eigen::Vector3d now =
        (positions[static_cast<size_t>(fv[0])] + positions[static_cast<size_t>(fv[1])] +
         positions[static_cast<size_t>(fv[2])]) /
        3.0;
    const double next = (p - now).dot(n);
    last_change = std::abs(next - dent);
    dent = next;
    ASSERT_LT(dent, tool_depth) << "step " << step << ": the surface passed the tool";
    ASSERT_GE(dent, 0.0) << "step " << step;
  }
  EXPECT_LT(last_change, 1e-7);  // settled, not swinging
  EXPECT_GT(dent, 0.2 * tool_depth);
  std::printf("[ tissue ] three segments 4 mm into the liver: dent settles at %.3f mm\n",
              1e3 * dent);
}

TEST(TissueWorld, TheDuctIsItsShellAndCanBePushedAndGrasped) {
  const Scene& scene = introductory_scene();
  const test::TempDir cache;
  const auto world = TissueWorld::build(scene, world_settings(cache.path()), nullptr).value();
  const int32_t duct = world->duct_organ();
  ASSERT_EQ(duct, organ_named(scene, "cystic_duct"));
  EXPECT_TRUE(world->two_sided(duct));
  // The shell lies on the scenario's duct: every node within half a wall of its outer surface,
  // inside it.
  const double wall = world->settings().duct_wall_thickness_m;
  const DuctFit fit = fit_duct(scene.organs[static_cast<size_t>(duct)].mesh, wall).value();
  const haptics::TriangleMesh& shell = world->surface(duct);
  for (const Eigen::Vector3d& p : shell.positions) {
    const Eigen::Vector3d d = fit.pose_WD.inverse() * p;
    EXPECT_NEAR(d.head<2>().norm(), 0.5 * (fit.duct.outer_diameter_m - wall), 1e-9);
  }
  // Its modes, for docs/tissue-parameters.md (the session's duct, not the models' 30 mm test
  // duct of docs/benchmarks.md).
  const Eigen::VectorXd& omega = world->model().duct().model->omega();
  std::printf(
      "[ duct ] the introductory scenario's duct: %.1f mm long, %.2f mm outside, %.2f mm wall; %d "
      "modes, %.1f-%.1f Hz\n",
      1e3 * fit.duct.length_m, 1e3 * fit.duct.outer_diameter_m, 1e3 * wall,
      static_cast<int>(omega.size()), omega(0) / (2.0 * M_PI),
      omega(omega.size() - 1) / (2.0 * M_PI));
  EXPECT_GT(omega(0), 0.0);
  // Jaws across the duct's middle from above, closing: the duct is grasped, squeezed, and moves.
  std::array<ToolModelInput, 2> tools{};
  tools[0].valid = true;
  const Eigen::Vector3d mid_D(0.0, 0.0, 0.5 * fit.duct.length_m);
  tools[0].jaws.hinge_W = fit.pose_WD * (mid_D + Eigen::Vector3d(0.0, 0.015, 0.0));
  Eigen::Matrix3d r_DJ;
  r_DJ.col(0) = Eigen::Vector3d::UnitX();  // opening across the duct
  r_DJ.col(1) = Eigen::Vector3d::UnitY();  // shaft up
  r_DJ.col(2) = r_DJ.col(0).cross(r_DJ.col(1));
  tools[0].jaws.rotation_WJ = fit.pose_WD.linear() * r_DJ;
  double squeeze_at_grasp = -1.0;
  for (int k = 0; k <= 70; ++k) {
    tools[0].jaws.opening_rad = std::max(0.05, 0.8 - 0.01 * k);
    world->step(tools, 0.005);
    if (world->duct_grasps()[0].grasping() && squeeze_at_grasp < 0.0) {
      squeeze_at_grasp = world->squeeze()[0];
    }
  }
  ASSERT_TRUE(world->duct_grasps()[0].grasping());
  EXPECT_GT(world->squeeze()[0], squeeze_at_grasp + 1e-3);
  EXPECT_GT(world->deepest_dent_m(), 1e-5);
  std::vector<SurfaceDeformation> d = world->make_deformations();
  world->write_deformations(&d);
  EXPECT_GT(d[static_cast<size_t>(duct)].count, 0);
}

// The introductory scenario's ductotomy: the faces it opens lie in its ellipse on the duct's wall
// (3 mm along, 2 mm around), on the side facing the laparoscope; the catheter meets the lumen
// with the scenario's friction. A centre off the wall is refused, naming the file, the line
// and the field.
TEST(TissueWorld, TheIntroductoryDuctHasItsIncision) {
  const Scene& scene = introductory_scene();
  const test::TempDir cache;
  const auto world = TissueWorld::build(scene, world_settings(cache.path()), nullptr).value();
  const int32_t duct = world->duct_organ();
  ASSERT_GE(duct, 0);
  const OrganTissue& t = world->model().organ(duct);
  EXPECT_DOUBLE_EQ(t.contact.friction_coefficient, 0.2);
  const IncisionSpec& cut = scene.organs[static_cast<size_t>(duct)].incision;
  ASSERT_TRUE(cut.present);
  ASSERT_EQ(t.open_faces.size(), t.surface.triangles.size());
  const DuctFit fit = fit_duct(scene.organs[static_cast<size_t>(duct)].mesh,
                               world->settings().duct_wall_thickness_m)
                          .value();
  const Eigen::Isometry3d pose_DW = fit.pose_WD.inverse();
  const Eigen::Vector3d c = pose_DW * cut.center_m;
  const double mid_radius = 0.5 * (fit.duct.outer_diameter_m - fit.duct.wall_thickness_m);
  int32_t open = 0;
  for (size_t f = 0; f < t.open_faces.size(); ++f) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const int32_t v : t.surface.triangles[f]) {
      centroid += t.surface.positions[static_cast<size_t>(v)];
    }
    const Eigen::Vector3d p = pose_DW * (centroid / 3.0);
    const double along = (p.z() - c.z()) / (0.5 * cut.length_m);
    const double around =
        mid_radius *
        std::remainder(std::atan2(p.y(), p.x()) - std::atan2(c.y(), c.x()), 2.0 * M_PI) /
        (0.5 * cut.width_m);
    EXPECT_EQ(t.open_faces[f] != 0, along * along + around * around <= 1.0) << f;
    open += t.open_faces[f];
  }
  // About the ellipse's area over a face's (quads of length / along by 2 pi r / around, halved).
  const double face_area =
      0.5 * (fit.duct.length_m / fit.duct.along) * (2.0 * M_PI * mid_radius / fit.duct.around);
  const double expected = M_PI * 0.25 * cut.length_m * cut.width_m / face_area;
  EXPECT_NEAR(open, expected, 0.35 * expected);
  // On the side facing the laparoscope.
  const Eigen::Vector3d to_camera = scene.scenario.camera.position_m - cut.center_m;
  const Eigen::Vector3d outward = fit.pose_WD.linear() * Eigen::Vector3d(c.x(), c.y(), 0.0);
  EXPECT_GT(to_camera.dot(outward), 0.0);
  std::printf(
      "[ incision ] the introductory duct's incision opens %d faces (ellipse / face: %.1f)\n", open,
      expected);

  Scene off = scene;
  off.organs[static_cast<size_t>(duct)].incision.center_m += 0.01 * Eigen::Vector3d::UnitY();
  const auto refused = TissueModel::build(off, world_settings(cache.path()), nullptr);
  ASSERT_FALSE(refused.ok());
  const Diagnostic& d = refused.diagnostics().front();
  EXPECT_EQ(d.file, scene.scenario.file.string());
  EXPECT_EQ(d.line, cut.line);
  EXPECT_EQ(d.field, "organs[" + std::to_string(duct) + "].incision");
  EXPECT_NE(d.message.find("from the duct's wall"), std::string::npos) << d.message;
}

TEST(TissueWorld, AFastSessionDeformsTheOrgansItsToolsPress) {
  const Scene& scene = introductory_scene();
  hardware::ScriptedTrajectory t;
  const Eigen::Vector3d a = default_handle_position(scene, 0, 0.05);
  const Eigen::Vector3d b = default_handle_position(scene, 0, 0.22);
  t.keyframes.push_back({0.0, a, Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back({1.0, b, Eigen::Quaterniond::Identity(), 0.8, 0});
  t.keyframes.push_back({1.5, b, Eigen::Quaterniond::Identity(), 0.8, 0});
  std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices{
      std::make_unique<hardware::ScriptedDevice>(t, "left"),
      std::make_unique<hardware::ScriptedDevice>(t, "right")};
  RuntimeSettings rs;
  rs.fast = true;
  rs.duration_s = 2.0;
  auto created = Session::create(scene, std::move(devices), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  auto session = std::move(created).value();
  (void)session->run();
  const ModelSnapshot& m = session->graphics_model();
  int32_t moved = 0;
  for (const SurfaceDeformation& d : m.organs) moved += d.count;
  EXPECT_GT(moved, 0);
  EXPECT_GT(m.deepest_dent_m, 1e-4);
  std::printf(
      "[ tissue ] fast session, a tool pressed in: %d vertices displaced, deepest %.3f mm\n", moved,
      1e3 * m.deepest_dent_m);
}

// The session's organs follow their tools at a bounded speed (SessionModel: 0.4 m/s, 2 mm a
// modelling step at the default 200 Hz; models::LocalDeformationSettings::max_move_per_step_m):
// the session's setting read, then a tissue world of the introductory scene stepped with it.
// 5 N on the liver (72 N/m: 69 mm of reading, its share held at max_displacement_m's 20 mm)
// dents it by about 2 mm a step until the 20 mm, not at once; released, it springs back the
// same way, not in one step. (Stepped without the limit, the same push makes the whole dent in
// the first step: checked last.)
TEST(TissueWorld, TheSessionsLiverGivesWayAndSpringsBackAtItsSpeed) {
  const Scene& scene = introductory_scene();
  RuntimeSettings rs;
  rs.fast = true;
  const auto session_model =
      SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
  ASSERT_TRUE(session_model.ok()) << session_model.message();
  const double step_m = session_model.value()->tissue().settings().local.max_move_per_step_m;
  EXPECT_DOUBLE_EQ(step_m, 0.002);
  const double dt_s = session_model.value()->timing().model_dt_s;
  EXPECT_DOUBLE_EQ(dt_s, 0.005);
  for (const double limit_m : {step_m, 0.0}) {
    const auto lw = liver_world(limit_m);
    ASSERT_GE(lw->liver, 0);
    const double max_dent_m = lw->world->settings().local.max_displacement_m;
    std::array<ToolModelInput, 2> tools = push_on_face_100(*lw, 5.0);
    std::vector<double> dents{0.0};  // the deepest dent after each step
    for (int step = 0; step < 15; ++step) {
      lw->world->step(tools, dt_s);
      dents.push_back(lw->world->deepest_dent_m());
    }
    tools[0].contact_count = 0;
    for (int step = 0; step < 15; ++step) {
      lw->world->step(tools, dt_s);
      dents.push_back(lw->world->deepest_dent_m());
    }
    std::printf("[ tissue world ] limit %.1f mm: the liver's deepest dent, pressed:",
                1e3 * limit_m);
    for (size_t i = 1; i < dents.size(); ++i)
      std::printf("%s %.2f", i == 16 ? "; released:" : "", 1e3 * dents[i]);
    std::printf(" mm\n");
    EXPECT_NEAR(dents[15], max_dent_m, 1e-9);  // pressed 15 steps: the whole dent
    EXPECT_EQ(dents[30], 0.0);                 // released 15 steps: at rest
    if (limit_m > 0.0) {
      // Each vertex moves 2 mm a step along its rest normal, and freely across it: where the
      // liver's normals turn from the push (its edge) the first step goes deeper (4.1 mm), the
      // rest by little more than 2 mm.
      EXPECT_LT(dents[1], 0.25 * max_dent_m);
      for (size_t i = 2; i < dents.size(); ++i) {
        EXPECT_LE(std::abs(dents[i] - dents[i - 1]), 1.1 * limit_m) << "step " << i;
      }
      EXPECT_GT(dents[16], max_dent_m - 1.1 * limit_m);  // one step after the release
      EXPECT_GT(dents[20], 0.0);
    } else {
      EXPECT_NEAR(dents[1], max_dent_m, 1e-9);  // the whole dent in one step
      EXPECT_EQ(dents[16], 0.0);                // and gone in one
    }
  }
}

}  // namespace
}  // namespace lap::sim
