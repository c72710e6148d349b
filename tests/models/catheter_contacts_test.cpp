// Contacts between deformables (§7.6.3): catheter centre-line particles, with the catheter's
// radius, against an organ-like surface and against the duct's inner wall; reactions on both
// sides.

#include "models/catheter_contacts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "haptics/closest_point.h"
#include "haptics/setup/mesh_generators.h"
#include "models/modal_shell.h"

namespace lap::models {
namespace {

// A catheter dropped onto a block comes to rest lying on it, its centre line one radius above
// the top face, and the block carries its whole weight.
TEST(CatheterContacts, CatheterComesToRestOnABlockCarryingItsWeight) {
  const haptics::MeshDatabase block =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.4, 0.1, 0.1), 8));
  CatheterSettings cs;
  cs.gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  const CatheterModel model = CatheterModel::build(cs);
  CatheterState cath(model, Eigen::Vector3d(-0.15, 0.053, 0.0), Eigen::Vector3d::UnitX());
  SurfaceContactSettings settings;
  settings.clearance_m = model.radius_m();
  SurfaceTracking tracking(block, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(model.particle_count()));
  Eigen::Vector3d carried = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3000; ++k) {
    clear_contacts(&cath);
    const int32_t n = update_surface_contacts(block, Eigen::Isometry3d::Identity(), settings,
                                              &tracking, &cath, reactions);
    ASSERT_TRUE(step_catheter(model, &cath, 0.005));
    settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});
    carried.setZero();
    for (int32_t i = 0; i < n; ++i) carried += reactions[i].force_on_surface_W;
  }
  double mass = 0.0;
  for (int32_t i = 0; i < model.particle_count(); ++i) mass += model.mass_of(i);
  const double weight = mass * 9.81;
  // Each particle sags m g / k below its clearance: 1.8 µm here.
  for (const auto& p : cath.positions) {
    EXPECT_NEAR(p.y() - 0.05, model.radius_m(), 1e-5);
  }
  EXPECT_NEAR(carried.y(), -weight, 0.01 * weight);
  EXPECT_NEAR(carried.x(), 0.0, 1e-6 * weight);
  std::printf(
      "[ contacts ] catheter on a block: centre line %.4f mm above it (radius %.3f mm); "
      "block carries %.4g N of %.4g N\n",
      1e3 * (cath.positions[32].y() - 0.05), 1e3 * model.radius_m(), -carried.y(), weight);
}

// A catheter dropped onto a locally deformable organ (§6.5) sinks into it: its contacts are found
// against the organ's rest surface, so the groove it presses cannot feed back on them. It comes
// to rest (no step-to-step oscillation of the dent), each particle pressed m g / k into the rest
// surface, the groove drawn where the catheter lies, and the organ carrying its weight.
TEST(CatheterContacts, CatheterRestsInTheGrooveItPressesIntoAnOrgan) {
  // 5 mm between vertices along the catheter, 1.6 mm across: fine enough to draw the groove.
  const haptics::TriangleMesh box = haptics::make_box(Eigen::Vector3d(0.32, 0.1, 0.1), 64);
  const haptics::MeshDatabase rest = haptics::MeshDatabase::build(box);
  haptics::MeshDatabase organ = haptics::MeshDatabase::build(box);  // the dented one
  LocalDeformationSettings ls;
  ls.radius_m = 0.02;
  ls.profile = DeformationProfile::kSmooth;
  const LocalDeformationModel local = LocalDeformationModel::build(rest, ls);
  LocalDeformationState dented(local);
  haptics::MeshUpdateScratch scratch(organ);
  CatheterSettings cs;
  cs.gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  const CatheterModel model = CatheterModel::build(cs);
  CatheterState cath(model, Eigen::Vector3d(-0.15, 0.0505, 0.0), Eigen::Vector3d::UnitX());
  SurfaceContactSettings settings;
  settings.clearance_m = model.radius_m();
  settings.stiffness_n_per_m = 0.5;  // soft tissue per particle: a groove a third of a mm deep
  SurfaceTracking tracking(rest, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(model.particle_count()));
  std::vector<DeformationContact> dents(reactions.size());
  std::vector<double> depth_history;
  Eigen::Vector3d carried = Eigen::Vector3d::Zero();
  for (int k = 0; k < 2000; ++k) {
    clear_contacts(&cath);
    const int32_t n = update_surface_contacts(rest, Eigen::Isometry3d::Identity(), settings,
                                              &tracking, &cath, reactions);
    ASSERT_TRUE(step_catheter(model, &cath, 0.005));
    settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});
    const int32_t d =
        catheter_dents(local, rest, Eigen::Isometry3d::Identity(), settings.stiffness_n_per_m,
                       {reactions.data(), static_cast<size_t>(n)}, dents);
    ASSERT_TRUE(deform(local, {dents.data(), static_cast<size_t>(d)}, &dented));
    organ.set_positions(dented.positions, dented.changed, &scratch);
    double deepest = 0.0;
    for (int32_t v = 0; v < local.vertex_count(); ++v) {
      if (local.rest_position(v).y() > 0.049) {
        deepest = std::max(deepest, 0.05 - dented.positions[static_cast<size_t>(v)].y());
      }
    }
    depth_history.push_back(deepest);
    carried.setZero();
    for (int32_t i = 0; i < n; ++i) carried += reactions[i].force_on_surface_W;
  }
  double mass = 0.0;
  for (int32_t i = 0; i < model.particle_count(); ++i) mass += model.mass_of(i);
  const double weight = mass * 9.81;
  EXPECT_NEAR(carried.y(), -weight, 0.01 * weight);
  // Steady: over the last 100 steps the groove's depth moves by less than 0.1 %.
  const auto [lo, hi] = std::minmax_element(depth_history.end() - 100, depth_history.end());
  EXPECT_LT(*hi - *lo, 1e-3 * *hi);
  // Each interior particle sits m g / k into the rest surface; the dented surface below it (brute
  // force over every face) lies one radius from its centre line, to a tenth of the depth.
  const double sink = model.mass_of(32) * 9.81 / settings.stiffness_n_per_m;
  double worst = 0.0;
  for (int32_t i = 2; i < model.particle_count() - 2; ++i) {
    const Eigen::Vector3d& p = cath.positions[static_cast<size_t>(i)];
    // Away from the ends (whose lighter end particles the bending stiffness lifts a little),
    // each particle carries its own weight on its own spring.
    if (i >= 16 && i < 48) {
      EXPECT_NEAR(0.05 - (p.y() - model.radius_m()), sink, 0.02 * sink) << "particle " << i;
    }
    double nearest = 1.0;
    for (int32_t f = 0; f < organ.face_count(); ++f) {
      const auto& fv = organ.face_vertices(f);
      haptics::TriangleFeature feature;
      nearest = std::min(
          nearest, (haptics::closest_on_triangle(p, organ.position(fv[0]), organ.position(fv[1]),
                                                 organ.position(fv[2]), &feature) -
                    p)
                       .norm());
    }
    worst = std::max(worst, std::abs(nearest - model.radius_m()));
  }
  EXPECT_LT(worst, 0.1 * sink);
  std::printf(
      "[ contacts ] catheter in an organ (k = %.1f N/m per particle): sinks %.3f mm, "
      "groove %.3f mm deep, surface within %.4f mm of the catheter's, depth varies %.2e "
      "over the last 100 steps; organ carries %.4g N of %.4g N\n",
      settings.stiffness_n_per_m, 1e3 * sink, 1e3 * depth_history.back(), 1e3 * worst, *hi - *lo,
      -carried.y(), weight);
}

// A short catheter pushed sideways against the default duct's wall, from inside (starting on the
// axis) or from outside (starting beside it, across it), with the side fixed by `from_inside` or
// tracked per particle (`keep_side`, for a catheter that may be on either side).
struct DuctPush {
  double min_radius = 1.0;  ///< of the centre line from the duct's axis, over the whole run
  double max_radius = 0.0;
  double on_wall_x = 0.0;  ///< the wall's share of the push at the end
  double applied_x = 0.0;
  double dent_x = 0.0;  ///< the pushed node's displacement
  double final_radius = 0.0;
};

DuctPush push_against_duct(bool outside, bool keep_side) {
  const DuctSettings duct;
  const DuctShell shell = make_duct_shell(duct);
  const ModalShellModel duct_model =
      ModalShellModel::build(shell.mesh, shell.held_dof, default_duct_modal_settings(duct));
  ModalShellState duct_state(duct_model);
  haptics::MeshDatabase wall = haptics::MeshDatabase::build(triangulate(shell.mesh));
  haptics::MeshUpdateScratch scratch(wall);
  std::vector<Eigen::Vector3d> positions = shell.mesh.nodes;
  std::vector<int32_t> all(positions.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int32_t>(i);

  CatheterSettings cs;
  cs.particles = 13;
  cs.length_m = 0.024;
  // Moved slowly through the surrounding tissue (quasi-static): without this drag the 0.3 g
  // catheter would reach metres per second under the push and cross the wall within one 5 ms
  // modelling step; contacts are checked per step, not swept.
  cs.drag_n_s_per_m = 0.05;
  const CatheterModel model = CatheterModel::build(cs);
  // Inside: along the axis. Outside: across the duct (along y), 5.3 mm off its axis on −x (just
  // beyond the clearance: the held catheter bends little), pushed +x.
  CatheterState cath =
      outside
          // Just clear of the duct's outer surface (0.05 mm), crossing it.
          ? CatheterState(model,
                          Eigen::Vector3d(-(0.5 * duct.outer_diameter_m + model.radius_m() + 5e-5),
                                          -0.012, 0.015),
                          Eigen::Vector3d::UnitY())
          : CatheterState(model, Eigen::Vector3d(0.0, 0.0, 0.003), Eigen::Vector3d::UnitZ());
  if (outside) {
    // Held at both ends, as a hand and the trocar would: pushed free, it slides off the round,
    // frictionless duct to one side.
    cath.fixed.front() = cath.fixed.back() = 1;
  }
  SurfaceContactSettings settings;
  settings.clearance_m = model.radius_m() + 0.5 * duct.wall_thickness_m;
  settings.from_inside = !keep_side;
  settings.keep_side = keep_side;
  settings.stiffness_n_per_m = 200.0;
  SurfaceTracking tracking(wall, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(model.particle_count()));
  const double push = 0.002;  // N per particle, along +x
  Eigen::Vector3d on_wall = Eigen::Vector3d::Zero();
  DuctPush out;
  for (int k = 0; k < 2000; ++k) {
    clear_contacts(&cath);
    const int32_t n = update_surface_contacts(wall, Eigen::Isometry3d::Identity(), settings,
                                              &tracking, &cath, reactions);
    // The push builds up over a second (a hand, not a blow: no particle may jump the wall).
    const double ramp = std::min(1.0, k / 200.0);
    for (auto& f : cath.external_force) f = Eigen::Vector3d(ramp * push, 0.0, 0.0);
    EXPECT_TRUE(step_catheter(model, &cath, 0.005));
    settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});
    on_wall.setZero();
    for (int32_t i = 0; i < n; ++i) {
      apply_surface_force(wall, reactions[i].primitive, reactions[i].point_O,
                          reactions[i].force_on_surface_W, &duct_state);
      on_wall += reactions[i].force_on_surface_W;
    }
    EXPECT_TRUE(step_modal_shell(duct_model, &duct_state, 0.005));
    for (size_t i = 0; i < positions.size(); ++i) {
      positions[i] = shell.mesh.nodes[i] + duct_state.displacement[i];
    }
    wall.set_positions(positions, all, &scratch);
    for (const auto& p : cath.positions) {
      // Only the part of the catheter over the duct's length can touch it.
      if (p.z() < 0.0 || p.z() > duct.length_m) continue;
      const double r = outside ? std::hypot(p.x(), p.y() - 0.0) : p.head<2>().norm();
      if (outside && std::abs(p.y()) > 0.002) continue;  // the crossing, beside the axis
      out.min_radius = std::min(out.min_radius, r);
      out.max_radius = std::max(out.max_radius, r);
    }
  }
  out.on_wall_x = on_wall.x();
  out.applied_x = push * model.particle_count();
  const int32_t pushed = duct.along / 2 * duct.around + (outside ? duct.around / 2 : 0);
  out.dent_x = duct_state.displacement[pushed].x();
  out.final_radius = cath.positions[6].head<2>().norm();
  return out;
}

// Inside the duct, pushed sideways: it stays inside, held by the inner wall; the wall takes the
// push (equal and opposite) and dents outwards. The same with the side tracked per particle.
TEST(CatheterContacts, CatheterPushedInsideTheDuctIsHeldByItsWall) {
  const double mid_radius =
      0.5 * (DuctSettings{}.outer_diameter_m - DuctSettings{}.wall_thickness_m);
  for (const bool keep_side : {false, true}) {
    const DuctPush r = push_against_duct(false, keep_side);
    // Inside: the centre line never reaches the wall's mid-surface.
    EXPECT_LT(r.max_radius, mid_radius);
    EXPECT_NEAR(r.on_wall_x, r.applied_x, 0.01 * r.applied_x);
    EXPECT_GT(r.dent_x, 0.0);  // outwards where pushed (node at angle 0, mid-length)
    std::printf(
        "[ contacts ] catheter pushed with %.3g N inside the duct (%s): wall takes %.4g N, "
        "centre line at %.3f mm of the %.3f mm mid-surface radius, wall dent %.4f mm\n",
        r.applied_x, keep_side ? "side tracked" : "from inside", r.on_wall_x, 1e3 * r.final_radius,
        1e3 * mid_radius, 1e3 * r.dent_x);
  }
}

// Outside the duct, lying across it and pushed against it: with the side tracked it stays
// outside, the wall takes the push and dents inwards.
TEST(CatheterContacts, CatheterPushedAgainstTheDuctFromOutsideStaysOutside) {
  const double mid_radius =
      0.5 * (DuctSettings{}.outer_diameter_m - DuctSettings{}.wall_thickness_m);
  const DuctPush r = push_against_duct(true, true);
  EXPECT_GT(r.min_radius, mid_radius);
  // The held ends take most of the push (the catheter is stiff over 24 mm); the wall the rest.
  EXPECT_GT(r.on_wall_x, 0.05 * r.applied_x);
  EXPECT_LT(r.on_wall_x, r.applied_x);
  EXPECT_GT(r.dent_x, 0.0);  // the near wall (angle π, facing −x) pushed towards +x: inwards
  std::printf(
      "[ contacts ] catheter pushed with %.3g N against the duct from outside: wall takes "
      "%.4g N, centre line never nearer the axis than %.3f mm (mid-surface %.3f mm)\n",
      r.applied_x, r.on_wall_x, 1e3 * r.min_radius, 1e3 * mid_radius);
}

// A particle beyond a surface's box is not searched; when it comes back it finds its nearest
// point afresh. Here the surface is two separate blocks: the catheter leaves the first, goes far
// away and comes down onto the second, which the local search could never walk to from the
// first. Every particle's contact is then on the second block, at the nearest point an
// exhaustive search finds.
TEST(CatheterContacts, AParticleComingBackFromAfarFindsItsNearestPointAfresh) {
  haptics::TriangleMesh two = haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4);
  const haptics::TriangleMesh second = haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4);
  const auto offset = static_cast<int32_t>(two.positions.size());
  for (const Eigen::Vector3d& p : second.positions) {
    two.positions.push_back(p + Eigen::Vector3d(0.3, 0.0, 0.0));
  }
  for (const haptics::Triangle& t : second.triangles) {
    two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  const haptics::MeshDatabase blocks = haptics::MeshDatabase::build(two);
  const CatheterModel model = CatheterModel::build({});
  CatheterState cath(model, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  SurfaceContactSettings settings;
  settings.clearance_m = model.radius_m();
  const auto n = static_cast<size_t>(model.particle_count());
  // Resting in a line on the first block's top, 0.3 mm into the clearance.
  auto lay = [&](double x0, double y) {
    for (size_t i = 0; i < n; ++i) {
      cath.positions[i] = Eigen::Vector3d(x0 + 0.09 * static_cast<double>(i) / (n - 1), y,
                                          -0.03 + 0.06 * static_cast<double>(i) / (n - 1));
    }
  };
  const double y_touching = 0.05 + model.radius_m() - 0.0003;
  lay(-0.045, y_touching);
  SurfaceTracking tracking(blocks, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(n);
  auto contacts = [&] {
    clear_contacts(&cath);
    return update_surface_contacts(blocks, Eigen::Isometry3d::Identity(), settings, &tracking,
                                   &cath, reactions);
  };
  EXPECT_EQ(contacts(), static_cast<int32_t>(n));
  // Lifted 1 m: beyond the box, nothing searched, no contact.
  lay(-0.045, 1.0);
  EXPECT_EQ(contacts(), 0);
  EXPECT_EQ(std::count(tracking.away.begin(), tracking.away.end(), 1), static_cast<ptrdiff_t>(n));
  // Down onto the second block.
  lay(0.255, y_touching);
  ASSERT_EQ(contacts(), static_cast<int32_t>(n));
  for (size_t k = 0; k < n; ++k) {
    const SurfaceReaction& r = reactions[k];
    const Eigen::Vector3d& p = cath.positions[static_cast<size_t>(r.particle)];
    double best = 1e300;
    for (int32_t f = 0; f < blocks.face_count(); ++f) {
      const auto& v = blocks.face_vertices(f);
      haptics::TriangleFeature feature;
      best = std::min(best,
                      (haptics::closest_on_triangle(p, blocks.position(v[0]), blocks.position(v[1]),
                                                    blocks.position(v[2]), &feature) -
                       p)
                          .squaredNorm());
    }
    EXPECT_NEAR((r.point_O - p).squaredNorm(), best, 1e-15) << "particle " << r.particle;
    EXPECT_GT(r.point_O.x(), 0.2);  // on the second block
    EXPECT_NEAR(cath.contact_offset[static_cast<size_t>(r.particle)], 0.05 + model.radius_m(),
                1e-12);
  }
  EXPECT_EQ(std::count(tracking.away.begin(), tracking.away.end(), 1), 0);
}

// Friction in the lumen (§7.6.3): a straight duct's wall held still, the catheter inside along
// its axis, every particle pressed by a side force onto the middle of a row of the wall's flat
// quads (at angle π / around, between two lines of nodes), so the contact normal is that row's
// and each particle bears N = side force in equilibrium.
struct Lumen {
  DuctSettings duct;
  haptics::MeshDatabase wall;
  CatheterModel model;
  SurfaceContactSettings settings;
  Lumen(int32_t particles, double length_m, double drag, double mu)
      : wall(haptics::MeshDatabase::build(triangulate(make_duct_shell(duct).mesh))),
        model(make_model(particles, length_m, drag)) {
    settings.clearance_m = model.radius_m() + 0.5 * duct.wall_thickness_m;
    settings.keep_side = true;
    settings.stiffness_n_per_m = 200.0;
    settings.friction_coefficient = mu;
  }
  static CatheterModel make_model(int32_t particles, double length_m, double drag) {
    CatheterSettings cs;
    cs.particles = particles;
    cs.length_m = length_m;
    cs.drag_n_s_per_m = drag;
    return CatheterModel::build(cs);
  }
  // The side the particles are pressed to: the row of quads from angle 0 to 2π / around.
  [[nodiscard]] Eigen::Vector3d side() const {
    const double a = M_PI / duct.around;
    return {std::cos(a), std::sin(a), 0.0};
  }
  // Where the centre line rests on that row: its distance from the axis less the clearance.
  [[nodiscard]] Eigen::Vector3d resting(double z) const {
    const double to_row =
        0.5 * (duct.outer_diameter_m - duct.wall_thickness_m) * std::cos(M_PI / duct.around);
    return (to_row - settings.clearance_m) * side() + Eigen::Vector3d(0.0, 0.0, z);
  }
};

// One particle's speed along the lumen after `steps` with side force `side` and axial force
// `axial` on every particle (none held): Coulomb with its regularisation,
//   slip v: axial = b v + μ N v / max(v, v_stick).
double steady_slide_speed(Lumen* lumen, double side, double axial, int steps) {
  CatheterState cath(lumen->model, lumen->resting(0.008), Eigen::Vector3d::UnitZ());
  SurfaceTracking tracking(lumen->wall, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(lumen->model.particle_count()));
  for (int k = 0; k < steps; ++k) {
    clear_contacts(&cath);
    (void)update_surface_contacts(lumen->wall, Eigen::Isometry3d::Identity(), lumen->settings,
                                  &tracking, &cath, reactions);
    // The side force at once, the axial one after 0.1 s (the particle pressed on the wall).
    for (auto& f : cath.external_force) {
      f = side * lumen->side() + Eigen::Vector3d(0.0, 0.0, k >= 20 ? axial : 0.0);
    }
    EXPECT_TRUE(step_catheter(lumen->model, &cath, 0.005));
  }
  double v = 0.0;
  for (const auto& vi : cath.velocities) v += vi.z();
  return v / static_cast<double>(cath.velocities.size());
}

// Pushed along the lumen harder than friction allows, it slides at the speed where drag takes
// the rest: (F − μ N) / b; pushed less, it holds, creeping at F / (μ N / v_stick + b) < v_stick.
TEST(CatheterContacts, InTheLumenItSlidesPastMuNAndHoldsBelow) {
  const double mu = 0.2;
  const double side = 0.002;  // N per particle: N = 2 mN
  Lumen lumen(5, 0.008, 0.05, mu);
  const double b = lumen.model.settings().drag_n_s_per_m;
  const double v_stick = lumen.model.settings().contact_stick_speed_m_per_s;
  const double slide = steady_slide_speed(&lumen, side, 1.5 * mu * side, 200);
  EXPECT_NEAR(slide, 0.5 * mu * side / b, 0.05 * 0.5 * mu * side / b);
  const double creep = steady_slide_speed(&lumen, side, 0.5 * mu * side, 200);
  const double creep_expected = 0.5 * mu * side / (mu * side / v_stick + b);
  EXPECT_NEAR(creep, creep_expected, 0.05 * creep_expected);
  EXPECT_LT(creep, v_stick);
  // Without friction it would slide at F / b.
  Lumen frictionless(5, 0.008, 0.05, 0.0);
  const double free = steady_slide_speed(&frictionless, side, 0.5 * mu * side, 200);
  EXPECT_NEAR(free, 0.5 * mu * side / b, 0.05 * 0.5 * mu * side / b);
  std::printf(
      "[ contacts ] in the lumen, N = %.3g N, mu = %.2f: pushed 1.5 mu N slides at %.4f mm/s "
      "(Coulomb %.4f), pushed 0.5 mu N creeps at %.4f mm/s (expected %.4f, v_stick %.2f; "
      "frictionless %.3f)\n",
      side, mu, 1e3 * slide, 1e3 * 0.5 * mu * side / b, 1e3 * creep, 1e3 * creep_expected,
      1e3 * v_stick, 1e3 * free);
}

// The catheter drawn through the lumen at a steady 10 mm/s by a stiff axial anchor on its front
// end: the anchor pulls with μ Σ N plus the drag n b v, and the wall bears μ Σ N along the axis
// (its reactions' axial sum), with Σ N the reactions' normal parts; both within 5 %.
TEST(CatheterContacts, DrawnThroughTheLumenTheResistanceIsCoulombs) {
  const double mu = 0.3;
  const double side = 0.002;
  Lumen lumen(13, 0.018, 2e-4, mu);
  const CatheterModel& model = lumen.model;
  CatheterState cath(model, lumen.resting(0.003), Eigen::Vector3d::UnitZ());
  SurfaceTracking tracking(lumen.wall, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(model.particle_count()));
  const double speed = 0.01;
  const double dt = 0.005;
  const int last = model.particle_count() - 1;
  const Eigen::Vector3d start = cath.positions[static_cast<size_t>(last)];
  double pull = 0.0;
  double wall_axial = 0.0;
  double wall_normal = 0.0;
  double pull_sum = 0.0;
  double axial_sum = 0.0;
  double normal_sum = 0.0;
  int samples = 0;
  for (int k = 0; k < 160; ++k) {                   // 0.8 s: 8 mm, within the 30 mm duct
    const double t = std::max(0.0, (k - 40) * dt);  // pressed on the wall first, for 0.2 s
    clear_anchors(&cath);
    CenterlineAnchor a;
    a.segment = last - 1;
    a.t = 1.0;
    // Along the axis only: across it the target is where the front end is, so the anchor does
    // not take the side force off the wall.
    a.target_W = cath.positions[static_cast<size_t>(last)];
    a.target_W.z() = start.z() + speed * t;
    a.stiffness_n_per_m = 20000.0;
    a.damping_n_s_per_m = 1.0;
    ASSERT_TRUE(add_anchor(model, a, &cath));
    clear_contacts(&cath);
    const int32_t n = update_surface_contacts(lumen.wall, Eigen::Isometry3d::Identity(),
                                              lumen.settings, &tracking, &cath, reactions);
    for (auto& f : cath.external_force) f = side * lumen.side();
    ASSERT_TRUE(step_catheter(model, &cath, dt));
    settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});
    const Eigen::Vector3d tip = cath.positions[static_cast<size_t>(last)];
    pull = a.stiffness_n_per_m * (a.target_W - tip).z() -
           a.damping_n_s_per_m * cath.velocities[static_cast<size_t>(last)].z();
    wall_axial = 0.0;
    wall_normal = 0.0;
    for (int32_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& f = reactions[static_cast<size_t>(i)].force_on_surface_W;
      wall_axial += f.z();
      wall_normal += f.head<2>().norm();
    }
    if (k >= 40) {
      EXPECT_EQ(n, model.particle_count());  // every particle on the wall
    }
    if (k >= 120) {  // the last 0.2 s: steady
      pull_sum += pull;
      axial_sum += wall_axial;
      normal_sum += wall_normal;
      ++samples;
    }
  }
  pull = pull_sum / samples;
  wall_axial = axial_sum / samples;
  wall_normal = normal_sum / samples;
  const double drag = model.particle_count() * model.settings().drag_n_s_per_m * speed;
  const double coulomb = mu * model.particle_count() * side;
  // The wall bears the side forces (less the little the front anchor, a step behind, takes).
  EXPECT_NEAR(wall_normal, model.particle_count() * side, 0.02 * model.particle_count() * side);
  EXPECT_NEAR(pull, coulomb + drag, 0.05 * (coulomb + drag));
  EXPECT_NEAR(pull, mu * wall_normal + drag, 0.05 * (mu * wall_normal + drag));
  EXPECT_NEAR(wall_axial, mu * wall_normal, 0.05 * mu * wall_normal);
  std::printf(
      "[ contacts ] drawn through the lumen at %.0f mm/s, %d particles, N = %.4g N in all, "
      "mu = %.2f: pulled with %.5g N (mu sum N + drag = %.5g N), the wall bears %.5g N along "
      "the axis (mu sum N = %.5g N)\n",
      1e3 * speed, model.particle_count(), wall_normal, mu, pull, coulomb + drag, wall_axial,
      mu * wall_normal);
}

// Entering the duct (§7.4, Figure 7-18): a catheter pointed at the duct's wall and pushed
// (its back two particles held, as a grasp does, and moved at 5 mm/s) passes into the lumen
// through an incision (faces marked open), and not through the intact wall; pointed along the
// axis at an open end, it enters there. The wall is the modal shell, deforming under the
// reactions; the lumen has friction.
struct Entry {
  bool entered = false;  ///< the tip ended inside the mid-surface, between the ends
  /// Where along the duct the tip first passed to the wall's inner side [m] (NaN: never).
  double entry_z = std::numeric_limits<double>::quiet_NaN();
  double inside_m = 0.0;                     ///< catheter length inside the lumen at the end
  double max_push_n = 0.0;                   ///< the largest push the holding anchors gave
  std::vector<std::array<double, 2>> curve;  ///< (length inside [m], push along the motion [N])
  /// At the curve's samples: the wall's normal reactions summed, Σ N [N], and their tangential
  /// parts (the friction) summed, Σ |F_t| [N].
  std::vector<std::array<double, 2>> wall;
  double push_work_j = 0.0;      ///< Σ push × the hand's travel
  double friction_loss_j = 0.0;  ///< Σ |F_t| |v_slip| dt: what the wall's friction dissipated
};

// Faces of the triangulated tube whose centroid is within `radius` (arc and axial distance)
// of the wall point at angle `angle`, height `z`: a hand-made incision.
std::vector<uint8_t> open_patch(const haptics::TriangleMesh& wall, double angle, double z,
                                double radius, double mid_radius) {
  std::vector<uint8_t> open(wall.triangles.size(), 0);
  for (size_t f = 0; f < open.size(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const int32_t v : wall.triangles[f]) c += wall.positions[static_cast<size_t>(v)];
    c /= 3.0;
    const double arc = mid_radius * std::remainder(std::atan2(c.y(), c.x()) - angle, 2.0 * M_PI);
    open[f] = std::hypot(arc, c.z() - z) <= radius ? 1 : 0;
  }
  return open;
}

Entry push_into_duct(const Eigen::Vector3d& tip, const Eigen::Vector3d& direction,
                     double distance_m, const std::vector<uint8_t>* open_faces, double mu) {
  const DuctSettings duct;
  const DuctShell shell = make_duct_shell(duct);
  const ModalShellModel duct_model =
      ModalShellModel::build(shell.mesh, shell.held_dof, default_duct_modal_settings(duct));
  ModalShellState duct_state(duct_model);
  const haptics::TriangleMesh mesh = triangulate(shell.mesh);
  haptics::MeshDatabase wall = haptics::MeshDatabase::build(mesh);
  haptics::MeshUpdateScratch scratch(wall);
  std::vector<Eigen::Vector3d> positions = shell.mesh.nodes;
  std::vector<int32_t> all(positions.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int32_t>(i);
  const double mid_radius = 0.5 * (duct.outer_diameter_m - duct.wall_thickness_m);

  CatheterSettings cs;  // the introductory scenario's 5 Fr catheter, 4.8 mm per segment
  cs.particles = 13;
  cs.length_m = 0.06;
  cs.outer_diameter_m = 0.00167;
  cs.linear_density_kg_per_m = 2.4e-3;
  cs.drag_n_s_per_m = 0.01;  // through the surrounding tissue, quasi-static (as above)
  const CatheterModel model = CatheterModel::build(cs);
  const Eigen::Vector3d d = direction.normalized();
  const int last = model.particle_count() - 1;
  // Tip first: particle 0 is the tip, the back end is held.
  CatheterState cath(model, tip, -d);
  SurfaceContactSettings settings;
  settings.clearance_m = model.radius_m() + 0.5 * duct.wall_thickness_m;
  settings.keep_side = true;
  settings.stiffness_n_per_m = 170.0;  // the introductory scenario's duct
  settings.damping_n_s_per_m = 0.2;
  settings.friction_coefficient = mu;
  SurfaceTracking tracking(wall, Eigen::Isometry3d::Identity(), cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(model.particle_count()));
  const std::span<const uint8_t> open =
      open_faces != nullptr ? std::span<const uint8_t>(*open_faces) : std::span<const uint8_t>();
  const std::array<Eigen::Vector3d, 2> held = {cath.positions[static_cast<size_t>(last - 1)],
                                               cath.positions[static_cast<size_t>(last)]};
  const double speed = 0.005;
  const double dt = 0.005;
  const int steps = static_cast<int>(distance_m / speed / dt);
  Entry out;
  for (int k = 0; k <= steps; ++k) {
    clear_anchors(&cath);
    for (int a = 0; a < 2; ++a) {
      CenterlineAnchor an;
      an.segment = last - 1;
      an.t = a;
      an.target_W = held[static_cast<size_t>(a)] + speed * dt * k * d;
      an.stiffness_n_per_m = 20000.0;
      an.damping_n_s_per_m = 0.0;  // the push is the springs' alone (a damper would add c v)
      add_anchor(model, an, &cath);
    }
    clear_contacts(&cath);
    const int32_t n = update_surface_contacts(wall, Eigen::Isometry3d::Identity(), settings,
                                              &tracking, &cath, reactions, open);
    EXPECT_TRUE(step_catheter(model, &cath, dt));
    settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});
    for (int32_t i = 0; i < n; ++i) {
      apply_surface_force(wall, reactions[i].primitive, reactions[i].point_O,
                          reactions[i].force_on_surface_W, &duct_state);
    }
    EXPECT_TRUE(step_modal_shell(duct_model, &duct_state, dt));
    for (size_t i = 0; i < positions.size(); ++i) {
      positions[i] = shell.mesh.nodes[i] + duct_state.displacement[i];
    }
    wall.set_positions(positions, all, &scratch);
    double push = 0.0;
    for (int a = 0; a < 2; ++a) {
      const CenterlineAnchor& an = cath.anchors[static_cast<size_t>(a)];
      const Eigen::Vector3d x = centerline_point(model, cath.positions, an.segment, an.t);
      push += an.stiffness_n_per_m * d.dot(an.target_W - x);
    }
    out.max_push_n = std::max(out.max_push_n, push);
    out.push_work_j += push * speed * dt;
    for (int32_t i = 0; i < n; ++i) {
      const SurfaceReaction& r = reactions[static_cast<size_t>(i)];
      const auto p = static_cast<size_t>(r.particle);
      const Eigen::Vector3d& nc = cath.contact_normal[p];
      const Eigen::Vector3d ft = r.force_on_surface_W - r.force_on_surface_W.dot(nc) * nc;
      const Eigen::Vector3d slip = cath.velocities[p] - cath.contact_surface_velocity[p];
      out.friction_loss_j += ft.norm() * (slip - slip.dot(nc) * nc).norm() * dt;
    }
    // The depth: how far along the lumen the tip has gone since it passed the wall.
    const Eigen::Vector3d& t = cath.positions.front();
    if (std::isnan(out.entry_z) && tracking.side[0] < 0) out.entry_z = t.z();
    const bool in = t.head<2>().norm() < mid_radius && t.z() > 0.0 && t.z() < duct.length_m;
    const double inside = in && !std::isnan(out.entry_z) ? std::abs(t.z() - out.entry_z) : 0.0;
    if (k % 20 == 0) {
      out.curve.push_back({inside, push});
      double normal = 0.0;
      double tangential = 0.0;
      for (int32_t i = 0; i < n; ++i) {
        const SurfaceReaction& r = reactions[static_cast<size_t>(i)];
        const Eigen::Vector3d& nc = cath.contact_normal[static_cast<size_t>(r.particle)];
        const double fn = r.force_on_surface_W.dot(nc);
        normal += std::abs(fn);
        tangential += (r.force_on_surface_W - fn * nc).norm();
      }
      out.wall.push_back({normal, tangential});
    }
    out.inside_m = inside;
  }
  const Eigen::Vector3d& t = cath.positions.front();
  out.entered = t.head<2>().norm() < mid_radius && t.z() > 0.0 && t.z() < duct.length_m;
  return out;
}

// A 3 mm ductotomy on the top of the default duct's wall (+y) at z_cut along it, and a catheter
// coming down onto it at 60 degrees to the axis, its tip 2 mm above the cut, pointing along the
// duct.
struct IncisionApproach {
  std::vector<uint8_t> open;
  Eigen::Vector3d tip;
  Eigen::Vector3d dir;
  explicit IncisionApproach(double z_cut) {
    const DuctSettings duct;
    const double mid_radius = 0.5 * (duct.outer_diameter_m - duct.wall_thickness_m);
    open = open_patch(triangulate(make_duct_shell(duct).mesh), M_PI / 2, z_cut, 0.0015, mid_radius);
    dir = Eigen::Vector3d(0.0, -std::sin(M_PI / 3), std::cos(M_PI / 3));
    tip = Eigen::Vector3d(0.0, mid_radius, z_cut) - (0.002 / std::sin(M_PI / 3)) * dir;
  }
};

TEST(CatheterContacts, TheCatheterEntersTheDuctThroughItsIncisionOnly) {
  const double z_cut = DuctSettings{}.length_m / 3.0;
  const IncisionApproach a(z_cut);
  ASSERT_GT(std::count(a.open.begin(), a.open.end(), 1), 4);
  const Entry through = push_into_duct(a.tip, a.dir, 0.010, &a.open, 0.3);
  const Entry intact = push_into_duct(a.tip, a.dir, 0.010, nullptr, 0.3);
  // Through the incision: in at the cut, and on along the lumen past it.
  EXPECT_TRUE(through.entered);
  EXPECT_NEAR(through.entry_z, z_cut, 0.0015);
  EXPECT_GT(through.inside_m, 0.003);
  // At the intact wall the tip is turned aside and slides along the duct's outside.
  EXPECT_FALSE(intact.entered);
  EXPECT_TRUE(std::isnan(intact.entry_z));
  EXPECT_EQ(intact.inside_m, 0.0);
  std::printf(
      "[ contacts ] into the duct at 60 degrees, 10 mm of push: through a 3 mm incision the tip "
      "enters %.2f mm from the cut's centre and is %.1f mm inside at the end (largest push "
      "%.3f N); at an intact wall it stays out (largest push %.3f N)\n",
      1e3 * (through.entry_z - z_cut), 1e3 * through.inside_m, through.max_push_n,
      intact.max_push_n);
}

TEST(CatheterContacts, TheCatheterEntersAnOpenEndOfTheDuct) {
  // Along the axis, its tip 2 mm before the end at z = 0.
  const Entry r = push_into_duct(Eigen::Vector3d(0.0, 0.0, -0.002), Eigen::Vector3d::UnitZ(), 0.012,
                                 nullptr, 0.3);
  EXPECT_TRUE(r.entered);
  EXPECT_LT(r.entry_z, 0.0015);  // at the rim (rounding it, a little before z = 0)
  EXPECT_GT(r.inside_m, 0.008);
}

// The insertion curve: the push against the tip's depth in the lumen, with and without friction in
// the lumen (μ = 0.3 and 0; docs/tissue-parameters.md prints it). Coulomb's law, checked two ways
// against what the wall bears: at every sample once the tip is 2 mm in, the wall's tangential
// reactions are μ times its normal ones (every contact slides: Σ |F_t| = μ Σ N); and over the
// whole insertion the hand's extra work with friction is what Coulomb friction dissipated,
// ∫ (P_μ − P_0) v dt = Σ ∫ μ N |v_slip| dt (the catheter's bending and the wall's dent being
// path-independent, their energy is the same with and without friction), both within 5 %.
TEST(CatheterContacts, InsertionForceAgainstDepth) {
  const double mu = 0.3;
  const IncisionApproach a(DuctSettings{}.length_m / 4.0);
  const Entry with = push_into_duct(a.tip, a.dir, 0.016, &a.open, mu);
  const Entry without = push_into_duct(a.tip, a.dir, 0.016, &a.open, 0.0);
  ASSERT_TRUE(with.entered);
  ASSERT_TRUE(without.entered);
  double mean_with = 0.0;
  double mean_without = 0.0;
  int checked = 0;
  std::printf("[ contacts ] insertion through the incision at 5 mm/s (every 0.1 s):\n");
  std::printf(
      "[ contacts ]   depth [mm]  push mu=0.3 [N]  sum N [N]  sum |F_t| / sum N  |  depth [mm]  "
      "push mu=0 [N]\n");
  for (size_t i = 0; i < with.curve.size() && i < without.curve.size(); ++i) {
    const double ratio = with.wall[i][0] > 0.0 ? with.wall[i][1] / with.wall[i][0] : 0.0;
    std::printf("[ contacts ]   %8.1f    %8.4f      %8.4f     %6.3f           |  %8.1f    %8.4f\n",
                1e3 * with.curve[i][0], with.curve[i][1], with.wall[i][0], ratio,
                1e3 * without.curve[i][0], without.curve[i][1]);
    mean_with += with.curve[i][1];
    mean_without += without.curve[i][1];
    if (with.curve[i][0] >= 0.002) {
      EXPECT_NEAR(ratio, mu, 0.05 * mu) << "at " << 1e3 * with.curve[i][0] << " mm";
      ++checked;
    }
  }
  EXPECT_GT(checked, 10);
  EXPECT_GT(mean_with, mean_without);
  const double extra_work = with.push_work_j - without.push_work_j;
  std::printf(
      "[ contacts ] the hand's work over the insertion: %.4e J with friction, %.4e J without; "
      "the extra %.4e J against Coulomb's dissipation %.4e J (%.1f %%)\n",
      with.push_work_j, without.push_work_j, extra_work, with.friction_loss_j,
      100.0 * (extra_work - with.friction_loss_j) / with.friction_loss_j);
  EXPECT_NEAR(extra_work, with.friction_loss_j, 0.05 * with.friction_loss_j);
  EXPECT_NEAR(without.friction_loss_j, 0.0, 1e-12);
}

}  // namespace
}  // namespace lap::models
