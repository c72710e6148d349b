// Local deformation (§6.5) against its formula, computed by brute force over every vertex, on a
// generated plate and box and on the real OpenHELP liver; the point proxy feeling the dent; and
// the stiffness a tool pressing into a dented organ feels, against (1 − share) k.

#include "models/local_deformation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <set>

#include "haptics/point_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "sim/runtime/tissue_world.h"
#include "sim/setup/mesh_loader.h"
#include "tests/test_support.h"

namespace lap::models {
namespace {

double expected_weight(DeformationProfile profile, double d, double r) {
  if (d >= r) return 0.0;
  if (profile == DeformationProfile::kLinear) return (r - d) / r;
  const double x = d / r;
  return (1.0 - x * x) * (1.0 - x * x);
}

// Every vertex against the formula, by brute force over the whole mesh: displaced by exactly
// Σ w(D) share P over the ordinary contacts plus the largest w(D) P of the conforming ones,
// untouched (bit for bit) beyond R of every contact.
void check_against_brute_force(const LocalDeformationModel& model,
                               std::span<const DeformationContact> contacts,
                               const LocalDeformationState& state, int32_t* moved_count) {
  const auto& s = model.settings();
  int32_t moved = 0;
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    const Eigen::Vector3d rest = model.rest_position(v);
    Eigen::Vector3d expected = rest;
    bool inside = false;
    Eigen::Vector3d conforming = Eigen::Vector3d::Zero();
    for (const DeformationContact& c : contacts) {
      const double d = (rest - c.point_O).norm();
      inside = inside || d < s.radius_m;
      const double w = expected_weight(s.profile, d, s.radius_m);
      if (!c.conform) {
        expected += w * s.surface_share * c.penetration_O;
      } else if ((w * c.penetration_O).norm() > conforming.norm()) {
        conforming = w * c.penetration_O;
      }
    }
    expected += conforming;
    if (inside) {
      ++moved;
      ASSERT_LT((state.positions[v] - expected).norm(), 1e-15) << "vertex " << v;
    } else {
      ASSERT_EQ(state.positions[v], rest) << "vertex " << v << " beyond R moved";
    }
  }
  *moved_count = moved;
}

DeformationContact contact_on_face(const haptics::MeshDatabase& db, int32_t f,
                                   const Eigen::Vector3d& bary, const Eigen::Vector3d& p) {
  const auto& fv = db.face_vertices(f);
  DeformationContact c;
  c.face = f;
  c.point_O =
      bary.x() * db.position(fv[0]) + bary.y() * db.position(fv[1]) + bary.z() * db.position(fv[2]);
  c.penetration_O = p;
  return c;
}

TEST(LocalDeformation, NeighbourListsAreTheVerticesWithinReach) {
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.06, 0.08), 12));
  LocalDeformationSettings settings;
  settings.radius_m = 0.015;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  const double reach = settings.radius_m + model.longest_edge_m();
  for (int32_t v = 0; v < model.vertex_count(); v += 7) {
    std::set<int32_t> expected;
    for (int32_t w = 0; w < model.vertex_count(); ++w) {
      if ((db.position(w) - db.position(v)).norm() <= reach) expected.insert(w);
    }
    const auto list = model.neighbours(v);
    const std::set<int32_t> got(list.begin(), list.end());
    EXPECT_EQ(got.size(), list.size()) << "duplicates in the list of " << v;
    EXPECT_EQ(got, expected) << "vertex " << v;
  }
}

TEST(LocalDeformation, DisplacementIsExactlyTheProfileAndNothingMovesBeyondR) {
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.06, 0.08), 16));
  for (const DeformationProfile profile :
       {DeformationProfile::kLinear, DeformationProfile::kSmooth}) {
    LocalDeformationSettings settings;
    settings.radius_m = 0.02;
    settings.profile = profile;
    settings.surface_share = 0.6;
    const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
    LocalDeformationState state(model);
    std::mt19937 rng(3);
    std::uniform_int_distribution<int32_t> face(0, db.face_count() - 1);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
      // One to four contacts at random points of random faces, pushing inwards 0-4 mm.
      std::vector<DeformationContact> contacts;
      for (int k = 0; k <= trial % 4; ++k) {
        const int32_t f = face(rng);
        Eigen::Vector3d b(u01(rng), u01(rng), 0.0);
        if (b.x() + b.y() > 1.0) b = Eigen::Vector3d(1.0 - b.x(), 1.0 - b.y(), 0.0);
        b.z() = 1.0 - b.x() - b.y();
        contacts.push_back(contact_on_face(db, f, b, -0.004 * u01(rng) * db.face_normal(f)));
        // The later trials mix in conforming contacts (a catheter's): largest, not summed.
        contacts.back().conform = trial >= 25 && (trial + k) % 2 == 1;
      }
      ASSERT_TRUE(deform(model, contacts, &state));
      int32_t moved = 0;
      check_against_brute_force(model, contacts, state, &moved);
      EXPECT_GT(moved, 0);
      EXPECT_EQ(static_cast<int32_t>(state.displaced.size()), moved);
    }
    // No contact: every vertex back at rest, and `changed` names each one that was displaced.
    const std::vector<int32_t> before = state.displaced;
    ASSERT_TRUE(deform(model, {}, &state));
    for (int32_t v = 0; v < model.vertex_count(); ++v) {
      ASSERT_EQ(state.positions[v], model.rest_position(v));
    }
    EXPECT_EQ(std::set<int32_t>(state.changed.begin(), state.changed.end()),
              std::set<int32_t>(before.begin(), before.end()));
    EXPECT_TRUE(state.displaced.empty());
  }
}

TEST(LocalDeformation, SmoothProfileHasNoCreaseAtTheRim) {
  LocalDeformationSettings settings;
  settings.radius_m = 0.01;
  settings.profile = DeformationProfile::kSmooth;
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.05, 0.05, 0.05), 2));
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  const double h = 1e-6;
  // Slope just inside the rim: the linear profile's is -1/R = -100 per metre; the smooth one's
  // goes to 0 with the distance to the rim (-8 x / R at x = 1 - 1.5e-4: about -0.12).
  EXPECT_NEAR((model.weight(0.01 - h) - model.weight(0.01 - 2 * h)) / h, 0.0, 0.2);
  EXPECT_DOUBLE_EQ(model.weight(0.0), 1.0);
  EXPECT_DOUBLE_EQ(model.weight(0.01), 0.0);
  EXPECT_DOUBLE_EQ(model.weight(0.02), 0.0);
}

TEST(LocalDeformation, BadInputIsRefusedOrIgnoredSafely) {
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.05, 0.05, 0.05), 4));
  LocalDeformationSettings bad;
  bad.radius_m = -1.0;
  EXPECT_THROW((void)LocalDeformationModel::build(db, bad), std::invalid_argument);
  bad = {};
  bad.surface_share = 1.5;
  try {
    (void)LocalDeformationModel::build(db, bad);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("surface_share"), std::string::npos);
  }
  const LocalDeformationModel model = LocalDeformationModel::build(db, {});
  LocalDeformationState state(model);
  DeformationContact c = contact_on_face(db, 0, {1.0, 0.0, 0.0}, {0.0, 0.0, -0.01});
  c.penetration_O.x() = std::nan("");
  EXPECT_FALSE(deform(model, {&c, 1}, &state));
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    ASSERT_EQ(state.positions[v], model.rest_position(v));
  }
  c = contact_on_face(db, 0, {1.0, 0.0, 0.0}, {0.0, 0.0, -0.01});
  c.face = db.face_count();
  EXPECT_FALSE(deform(model, {&c, 1}, &state));
  // A huge push is held at max_displacement_m.
  c = contact_on_face(db, 0, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0});
  EXPECT_TRUE(deform(model, {&c, 1}, &state));
  EXPECT_GT(state.clamped, 0);
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    EXPECT_LE((state.positions[v] - model.rest_position(v)).norm(),
              model.settings().max_displacement_m + 1e-15);
  }
}

TEST(LocalDeformation, RealLiverAgainstBruteForce) {
  LAP_REQUIRE_SHARED_MESHES();
  const auto dir = test::shared_meshes_dir();
  const haptics::MeshDatabase db = haptics::MeshDatabase::build(
      sim::load_mesh(dir / "liver_openhelp.stl", {0.001, 0.0}).value());
  LocalDeformationSettings settings;
  settings.radius_m = 0.02;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  LocalDeformationState state(model);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int32_t> face(0, db.face_count() - 1);
  int32_t most = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const int32_t f = face(rng);
    const DeformationContact c =
        contact_on_face(db, f, {0.2, 0.3, 0.5}, -0.005 * db.face_normal(f));
    ASSERT_TRUE(deform(model, {&c, 1}, &state));
    int32_t moved = 0;
    check_against_brute_force(model, {&c, 1}, state, &moved);
    most = std::max(most, moved);
  }
  std::printf(
      "[ local deformation ] liver %d vertices, R = 2 cm: up to %d moved, lists %.1f "
      "entries per vertex\n",
      model.vertex_count(), most,
      static_cast<double>(model.neighbour_entries()) / model.vertex_count());
}

// A push on the deformed surface (a proxy's contact) becomes a contact on the rest shape: the
// point keeps its barycentric place on its face, and the penetration is the tool's displacement
// into the rest surface: force / stiffness below the deformed point, measured from the rest one.
TEST(LocalDeformation, RestContactMapsAPushOnTheDeformedSurfaceBackToRest) {
  haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 10));
  LocalDeformationSettings settings;
  settings.radius_m = 0.03;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  LocalDeformationState state(model);
  // Dent the top, then take a point inside a dented face.
  int32_t face = -1;
  for (int32_t f = 0; f < db.face_count() && face < 0; ++f) {
    if (db.face_normal(f).y() > 0.99) face = f;
  }
  ASSERT_GE(face, 0);
  const auto& fv = db.face_vertices(face);
  DeformationContact dent;
  dent.face = face;
  dent.point_O = db.position(fv[0]);
  dent.penetration_O = Eigen::Vector3d(0.0, -0.006, 0.0);
  ASSERT_TRUE(deform(model, {&dent, 1}, &state));
  db.set_positions(state.positions, state.changed);
  const Eigen::Vector3d bary(0.2, 0.5, 0.3);
  const Eigen::Vector3d on_deformed =
      bary.x() * db.position(fv[0]) + bary.y() * db.position(fv[1]) + bary.z() * db.position(fv[2]);
  const Eigen::Vector3d force(0.001, -0.04, 0.0);
  const DeformationContact c =
      rest_contact(model, db, {haptics::PrimitiveKind::kFace, face}, on_deformed, force, 400.0);
  const Eigen::Vector3d on_rest = bary.x() * model.rest_position(fv[0]) +
                                  bary.y() * model.rest_position(fv[1]) +
                                  bary.z() * model.rest_position(fv[2]);
  EXPECT_EQ(c.face, face);
  EXPECT_LT((c.point_O - on_rest).norm(), 1e-15);
  EXPECT_LT((c.penetration_O - (on_deformed + force / 400.0 - on_rest)).norm(), 1e-17);
  // The surface there is 0.3 mm or more below rest: the tool is in deeper than force / k.
  EXPECT_GT((on_rest - on_deformed).y(), 3e-4);
  // On the rest surface (the catheter's contacts) it is force / stiffness.
  const haptics::MeshDatabase rest =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 10));
  const DeformationContact cr =
      rest_contact(model, rest, {haptics::PrimitiveKind::kFace, face}, on_rest, force, 400.0);
  EXPECT_LT((cr.penetration_O - force / 400.0).norm(), 1e-17);
  // On an edge: the point's place along it, and a face of the edge.
  const int32_t e = db.face_edges(face)[0];
  const auto& ev = db.edge_vertices(e);
  const Eigen::Vector3d mid = 0.25 * db.position(ev[0]) + 0.75 * db.position(ev[1]);
  const DeformationContact ce =
      rest_contact(model, db, {haptics::PrimitiveKind::kEdge, e}, mid, force, 400.0);
  EXPECT_LT(
      (ce.point_O - (0.25 * model.rest_position(ev[0]) + 0.75 * model.rest_position(ev[1]))).norm(),
      1e-15);
  EXPECT_GE(ce.face, 0);
}

// The deformed surface is the one the proxy feels: a probe coming straight down onto the dent's
// centre (a vertex of the top face) touches it share |P| below the rest surface.
TEST(LocalDeformation, PointProxyFeelsTheDeformedSurface) {
  haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 10));
  int32_t top = -1;  // the vertex at the centre of the top face (y = 0.05)
  for (int32_t v = 0; v < db.vertex_count(); ++v) {
    if ((db.position(v) - Eigen::Vector3d(0.0, 0.05, 0.0)).norm() < 1e-12) top = v;
  }
  ASSERT_GE(top, 0);
  int32_t face = -1;
  db.for_each_vertex_face(top, [&](int32_t f) { face = f; });
  LocalDeformationSettings settings;
  settings.radius_m = 0.03;
  settings.surface_share = 0.5;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  LocalDeformationState state(model);
  DeformationContact c;
  c.face = face;
  c.point_O = db.position(top);
  c.penetration_O = Eigen::Vector3d(0.0, -0.008, 0.0);
  ASSERT_TRUE(deform(model, {&c, 1}, &state));
  db.set_positions(state.positions, state.changed);

  haptics::HapticObject object;
  object.mesh = &db;
  haptics::PointProxy proxy;
  Eigen::Vector3d hip(0.0, 0.06, 0.0);
  proxy.reset(hip);
  double first_contact_y = 1.0;
  for (int i = 0; i < 300 && first_contact_y > 0.5; ++i) {
    hip.y() -= 1e-4;
    const haptics::PointProxyOutput out = proxy.step({&object, 1}, hip, 1e-3);
    if (out.contact_count > 0) first_contact_y = out.ihip_W.y();
  }
  // The rest surface is at 0.05; the dent's centre at 0.05 - 0.5 * 0.008 = 0.046.
  EXPECT_NEAR(first_contact_y, 0.046, 1e-4);
}

// What a tool pressing quasi-statically into a locally deformed organ feels. A point proxy's HIP
// is lowered x = 4 mm below the flat top of a box (stiffness k) straight under a vertex and held
// there; every fifth haptic tick (200 Hz) its contact goes to the modelling loop as a tool
// contact (sim::ToolModelInput, as the session sends it), and the proxy then feels the dented
// surface. Once the dent has settled, force / x must be (1 − s) k, s = surface_share, as
// local_deformation.h derives: the dent takes s of the tool's displacement. Taking the
// penetration as force / k alone (the depth below the dented surface, as before) settles at
// k / (1 + s) instead: 10 % stiffer at s = 0.3, 56 % at s = 0.6; the tolerance is 2 %.
struct FeltPress {
  double force_n = 0.0;    // on the tool, settled
  double dent_m = 0.0;     // the surface's deepest displacement, settled
  double last_change = 0;  // of the force over the last modelling step [N]
  int32_t contact_ticks = 0;
};

FeltPress press_box_top(double share, DeformationProfile profile, double k, double depth) {
  sim::Scene scene;
  sim::Organ organ;
  organ.name = "box";
  organ.mesh = haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 20);  // 5 mm squares
  organ.model = ModelKind::kLocal;
  organ.material.stiffness_n_per_m = k;
  scene.organs.push_back(std::move(organ));
  sim::TissueWorldSettings ws;
  ws.local.surface_share = share;
  ws.local.profile = profile;
  ws.local.radius_m = 0.02;
  ws.catheter_start_W = Eigen::Vector3d(1.0, 1.0, 1.0);  // far from the box: no contact
  const std::unique_ptr<sim::TissueWorld> world =
      sim::TissueWorld::build(scene, ws, nullptr).value();
  const haptics::TriangleMesh& rest = world->surface(0);
  haptics::MeshDatabase db = haptics::MeshDatabase::build(rest);
  haptics::HapticObject object;
  object.mesh = &db;
  object.law.stiffness_n_per_m = k;
  object.law.max_force_n = 100.0;
  haptics::PointProxy proxy;
  const Eigen::Vector3d top(0.0, 0.05, 0.0);  // a vertex: the centre of the top face
  Eigen::Vector3d hip = top + Eigen::Vector3d(0.0, 0.002, 0.0);
  proxy.reset(hip);
  std::array<sim::ToolModelInput, 2> tools{};
  tools[0].valid = true;
  tools[0].jaws.opening_rad = 0.8;
  std::vector<sim::SurfaceDeformation> published = world->make_deformations();
  std::vector<Eigen::Vector3d> positions = rest.positions;
  FeltPress r;
  double last_force = 0.0;
  for (int32_t tick = 0; tick < 400; ++tick) {
    hip.y() = std::max(top.y() - depth, hip.y() - 1e-4);  // down 0.1 mm per tick, then held
    const haptics::PointProxyOutput out = proxy.step({&object, 1}, hip, 1e-3);
    tools[0].contact_count = 0;
    if (out.contact_count > 0) {
      ++r.contact_ticks;
      sim::ToolContact& c = tools[0].contacts[0];
      c.organ = 0;
      c.primitive = out.primitive;
      c.point_W = out.ihip_W;
      c.force_on_organ_W = -out.force_W;
      tools[0].contact_count = 1;
    }
    r.force_n = out.force_W.norm();
    if (tick % 5 != 4) continue;
    // The modelling step, and the proxy's surface taking its deformation up.
    world->step(tools, 0.005);
    world->write_deformations(&published);
    positions = rest.positions;
    const sim::SurfaceDeformation& d = published[0];
    for (int32_t i = 0; i < d.count; ++i) {
      positions[static_cast<size_t>(d.vertex[static_cast<size_t>(i)])] =
          d.position[static_cast<size_t>(i)];
    }
    db.set_positions(positions);
    r.dent_m = world->deepest_dent_m();
    r.last_change = std::abs(r.force_n - last_force);
    last_force = r.force_n;
  }
  return r;
}

TEST(LocalDeformation, APressingToolFeelsOneMinusShareTimesTheStiffness) {
  const double k = 300.0;
  const double x = 0.004;
  for (const DeformationProfile profile :
       {DeformationProfile::kLinear, DeformationProfile::kSmooth}) {
    for (const double share : {0.3, 0.6}) {
      const FeltPress p = press_box_top(share, profile, k, x);
      const double felt = p.force_n / x;
      const double expected = (1.0 - share) * k;
      std::printf(
          "[ local deformation ] %s, share %.1f: felt %.2f N/m, (1 - s) k = %.2f, k / (1 + s) = "
          "%.2f; dent %.4f mm of s x = %.4f mm\n",
          profile == DeformationProfile::kLinear ? "linear" : "smooth", share, felt, expected,
          k / (1.0 + share), 1e3 * p.dent_m, 1e3 * share * x);
      EXPECT_GT(p.contact_ticks, 350);
      EXPECT_NEAR(felt, expected, 0.02 * expected) << "share " << share;
      EXPECT_NEAR(p.dent_m, share * x, 0.02 * share * x) << "share " << share;
      EXPECT_LT(p.last_change, 1e-6 * p.force_n) << "not settled";
    }
  }
}

}  // namespace
}  // namespace lap::models

namespace lap::models {
namespace {

// A dent does not carry the surface through a tool's segment that has no contact on the organ
// (DeformationObstacle): a thin slab (2 cm) pressed 1 cm down at the middle of its top, R = 3 cm,
// moves its bottom down too (the far side: by (1 - 2/3) of the dent's 5 mm there, 1.67 mm); a
// segment 1 mm under the bottom stops every vertex whose way down comes within one edge of it,
// 0.5 mm short of its level, exactly, and leaves the rest as without it; the pressing tool's own
// segment, lying in the dent, stops nothing (those vertices move into the slab); the same call
// again keeps them there; without the segment they go where the formula puts them. Released, the
// dent springs back: a segment lying across it 3 mm below the top stops the vertices coming up
// under it 0.5 mm short of its level, holds those that start within an edge of it above it
// (their nearest approach is where they are), and lets the rest go back to rest.
TEST(LocalDeformation, TheSurfaceDoesNotPassAToolThatDoesNotPressOnIt) {
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.02, 0.1), 20));
  LocalDeformationSettings settings;
  settings.radius_m = 0.03;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  Eigen::Vector3d on_top;
  DeformationContact press;
  press.face = db.nearest_face(Eigen::Vector3d(0.0, 0.011, 0.0), &on_top, nullptr);
  ASSERT_GE(press.face, 0);
  press.point_O = on_top;
  press.penetration_O = Eigen::Vector3d(0.0, -0.01, 0.0);
  const double level = -0.011;  // the segment: 1 mm under the bottom, along x
  const DeformationObstacle under{Eigen::Vector3d(-0.02, level, 0.0),
                                  Eigen::Vector3d(0.02, level, 0.0)};
  // The pressing tool's own segment, in the dent it makes (5 mm below the top's rest).
  const DeformationObstacle own{Eigen::Vector3d(-0.01, 0.005, 0.0),
                                Eigen::Vector3d(0.01, 0.005, 0.0)};
  LocalDeformationState free_state(model);
  ASSERT_TRUE(deform(model, {&press, 1}, &free_state));
  LocalDeformationState state(model);
  const std::array<DeformationObstacle, 2> obstacles{under, own};
  ASSERT_TRUE(deform(model, {&press, 1}, &state, obstacles));
  const double capture = model.longest_edge_m();
  int32_t stopped = 0;
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    const Eigen::Vector3d& rest = model.rest_position(v);
    const Eigen::Vector3d& free = free_state.positions[v];
    const Eigen::Vector3d& got = state.positions[v];
    // A bottom vertex moving straight down comes level with the segment at y = level, its
    // distance from it then that of its (x, z) from the segment's line piece; it stops 0.5 mm
    // short of that.
    const double dx = std::max(0.0, std::abs(rest.x()) - 0.02);
    const bool reaches =
        rest.y() < -0.0099 && free.y() < level && std::hypot(dx, rest.z()) < capture;
    if (reaches) {
      ++stopped;
      ASSERT_NEAR(got.y(), level + 0.0005, 1e-12) << "vertex " << v;
      ASSERT_EQ(got.x(), rest.x());
      ASSERT_EQ(got.z(), rest.z());
    } else {
      ASSERT_EQ(got, free) << "vertex " << v;
    }
  }
  EXPECT_GT(stopped, 10);
  EXPECT_EQ(state.stopped, stopped);
  // Held there while the segment stays; free once it goes.
  const std::vector<Eigen::Vector3d> held = state.positions;
  ASSERT_TRUE(deform(model, {&press, 1}, &state, obstacles));
  EXPECT_EQ(state.positions, held);
  ASSERT_TRUE(deform(model, {&press, 1}, &state));
  EXPECT_EQ(state.positions, free_state.positions);
  EXPECT_EQ(state.stopped, 0);
  // Released with a segment lying across the dent 3 mm below the top (the bottom moves up, into
  // the slab, away from the one under it).
  const double across = 0.007;
  const DeformationObstacle over{Eigen::Vector3d(-0.01, across, 0.0),
                                 Eigen::Vector3d(0.01, across, 0.0)};
  const std::array<DeformationObstacle, 2> released{under, over};
  ASSERT_TRUE(deform(model, {}, &state, released));
  int32_t held_up = 0;
  int32_t held_beside = 0;
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    const Eigen::Vector3d& rest = model.rest_position(v);
    const Eigen::Vector3d& from = free_state.positions[v];
    const double dx = std::max(0.0, std::abs(rest.x()) - 0.01);
    const bool top = rest.y() > 0.0099;
    if (top && from.y() < across && std::hypot(dx, rest.z()) < capture) {
      ++held_up;  // comes up level with it: 0.5 mm short (or stays, nearer than that)
      ASSERT_NEAR(state.positions[v].y(), std::max(from.y(), across - 0.0005), 1e-12)
          << "vertex " << v;
    } else if (top && std::hypot(std::hypot(dx, from.y() - across), rest.z()) < capture) {
      ++held_beside;  // starts beside it, within an edge: its nearest approach is where it is
      ASSERT_EQ(state.positions[v], from) << "vertex " << v;
    } else {
      ASSERT_EQ(state.positions[v], rest) << "vertex " << v;
    }
  }
  EXPECT_GT(held_up, 3);
  EXPECT_GT(held_beside, 0);
  EXPECT_EQ(state.stopped, held_up + held_beside);
  // Taken away, every vertex goes back to rest.
  ASSERT_TRUE(deform(model, {}, &state, {&under, 1}));
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    ASSERT_EQ(state.positions[v], model.rest_position(v));
  }
  std::printf(
      "[ local deformation ] a segment 1 mm under the slab stopped %d vertices; one across the "
      "released dent %d coming up to it and %d beside it\n",
      stopped, held_up, held_beside);
}

// The surface's speed (max_move_per_step_m, sim's kTissueSurfaceMPerS): pressed 10 mm into the
// middle of a box's top with share 0.5 (every vertex w(D) 5 mm down at once without the limit),
// each vertex goes down by at most 2 mm a call: exactly min(w(D) 5 mm, 2 mm × calls), by brute
// force over the whole mesh. Released, it comes back up the same way, max(0, w(D) 5 mm − 2 mm ×
// calls), exactly at rest with nothing listed as displaced in the end. Sideways (a move in the
// surface's plane) nothing is held back.
TEST(LocalDeformation, TheSurfaceGivesWayAndSpringsBackAtMostItsStepACall) {
  const haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.06, 0.08), 16));
  LocalDeformationSettings settings;
  settings.radius_m = 0.015;  // the dent stays 15 mm clear of the top's edges: its normal is +z
  settings.surface_share = 0.5;
  settings.max_move_per_step_m = 0.002;
  const LocalDeformationModel model = LocalDeformationModel::build(db, settings);
  LocalDeformationState state(model);
  DeformationContact c;
  c.face = db.nearest_face(Eigen::Vector3d(0.001, 0.002, 0.05), &c.point_O, nullptr);
  ASSERT_GE(c.face, 0);
  ASSERT_NEAR(c.point_O.z(), 0.04, 1e-12);  // on the top
  c.penetration_O = Eigen::Vector3d(0.0, 0.0, -0.010);
  // Every vertex's depth below rest against `expected(w(D) 5 mm)`; the deepest.
  auto check = [&](const char* when, int call, auto expected) {
    double deepest = 0.0;
    for (int32_t v = 0; v < model.vertex_count(); ++v) {
      const Eigen::Vector3d rest = model.rest_position(v);
      const double depth = expected(model.weight((rest - c.point_O).norm()) * 0.005);
      EXPECT_LT((state.positions[v] - (rest - depth * Eigen::Vector3d::UnitZ())).norm(), 1e-15)
          << when << " call " << call << ", vertex " << v;
      deepest = std::max(deepest, depth);
    }
    std::printf("[ local deformation ] %s, call %d: the deepest vertex %.3f mm down, %d held\n",
                when, call, 1e3 * deepest, state.slowed);
    EXPECT_NEAR(state.deepest_m, deepest, 1e-15);
    return deepest;
  };
  double full = 0.0;  // the formula's deepest vertex: w(D) 5 mm, a little short of 5 mm
  for (int32_t v = 0; v < model.vertex_count(); ++v) {
    full = std::max(full, model.weight((model.rest_position(v) - c.point_O).norm()) * 0.005);
  }
  ASSERT_GT(full, 0.004);  // three calls to get there
  for (int call = 1; call <= 3; ++call) {
    ASSERT_TRUE(deform(model, {&c, 1}, &state));
    check("pressed", call, [&](double d) { return std::min(d, 0.002 * call); });
    EXPECT_EQ(state.slowed > 0, call < 3);
  }
  for (int call = 1; call <= 3; ++call) {
    ASSERT_TRUE(deform(model, {}, &state));
    check("released", call, [&](double d) { return std::max(0.0, d - 0.002 * call); });
    EXPECT_EQ(state.slowed > 0, call < 3);
  }
  EXPECT_TRUE(state.displaced.empty());
  // Sideways: a pull in the top's plane moves the surface at once, however far.
  c.penetration_O = Eigen::Vector3d(0.010, 0.0, 0.0);
  ASSERT_TRUE(deform(model, {&c, 1}, &state));
  EXPECT_EQ(state.slowed, 0);
  EXPECT_NEAR(state.deepest_m, full, 1e-15);
  // The bound holds with the limit: held 4 mm deep (max_displacement_m), then pulled mostly
  // sideways, the vertices rise 2 mm and keep their sideways move only as far as the 4 mm allow
  // (without that, sqrt(2² + 4²) = 4.5 mm from rest).
  settings.max_displacement_m = 0.004;
  const LocalDeformationModel bounded = LocalDeformationModel::build(db, settings);
  LocalDeformationState held(bounded);
  c.penetration_O = Eigen::Vector3d(0.0, 0.0, -0.010);
  for (int call = 0; call < 3; ++call) ASSERT_TRUE(deform(bounded, {&c, 1}, &held));
  EXPECT_NEAR(held.deepest_m, 0.004, 1e-15);
  c.penetration_O = Eigen::Vector3d(0.020, 0.0, -0.001);
  ASSERT_TRUE(deform(bounded, {&c, 1}, &held));
  EXPECT_GT(held.slowed, 0);
  EXPECT_LE(held.deepest_m, 0.004 * (1.0 + 1e-15));
  for (int32_t v = 0; v < bounded.vertex_count(); ++v) {
    ASSERT_LE((held.positions[v] - bounded.rest_position(v)).norm(), 0.004 * (1.0 + 1e-15)) << v;
  }
  // A limit that is negative or not a number is refused, naming the setting.
  for (const double bad : {-0.001, std::nan("")}) {
    settings.max_move_per_step_m = bad;
    try {
      (void)LocalDeformationModel::build(db, settings);
      ADD_FAILURE() << "no error for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("max_move_per_step_m"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace lap::models
