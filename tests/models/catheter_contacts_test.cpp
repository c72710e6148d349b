// Contacts between deformables (§7.6.3): catheter centre-line particles, with the catheter's
// radius, against an organ-like surface and against the duct's inner wall; reactions on both
// sides.

#include "models/catheter_contacts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

}  // namespace
}  // namespace lap::models
