// The models allocate nothing in their steps: after setup, their steps allocate nothing (counting
// operator new over 1,000 steps each, with contacts, clamps and the catheter's energy guard at
// work).

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/setup/mesh_generators.h"
#include "models/catheter_contacts.h"
#include "models/catheter_grasp.h"
#include "models/catheter_model.h"
#include "models/duct_grasp.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "models/rigid_body.h"
#include "tests/support/counting_allocator.h"

namespace lap::models {
namespace {

TEST(ModelsAllocation, StepsAllocateNothing) {
  // Local deformation with the database update the proxies need.
  haptics::MeshDatabase db =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 12));
  const LocalDeformationModel local = LocalDeformationModel::build(db, {});
  LocalDeformationState local_state(local);
  haptics::MeshUpdateScratch scratch(db);
  // The duct's modes.
  DuctSettings duct;
  duct.around = 12;
  duct.along = 10;
  const DuctShell shell = make_duct_shell(duct);
  ModalShellSettings modal = default_duct_modal_settings(duct);
  modal.modes = 8;
  const ModalShellModel duct_model = ModalShellModel::build(shell.mesh, shell.held_dof, modal);
  ModalShellState duct_state(duct_model);
  // A catheter clamped at one end, pushed about, with a large start (each particle moved 1 cm,
  // s.d. per axis) that trips the guard: a 2 mm start tripped it in GCC's build, not in clang's.
  const CatheterModel catheter = CatheterModel::build({});
  CatheterState cath(catheter, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  cath.fixed[0] = cath.fixed[1] = 1;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto& p : cath.positions) p += 0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng));
  // The catheter lies on a block and is grasped by jaws that close and open.
  const haptics::MeshDatabase block =
      haptics::MeshDatabase::build(haptics::make_box(Eigen::Vector3d(0.4, 0.1, 0.1), 4));
  const Eigen::Isometry3d block_pose(Eigen::Translation3d(0.0, -0.0513, 0.0));
  SurfaceTracking tracking(block, block_pose, cath);
  std::vector<SurfaceReaction> reactions(static_cast<size_t>(catheter.particle_count()));
  GraspState grasp;
  JawFrame jaws;
  jaws.hinge_W = Eigen::Vector3d(0.1, 0.01, 0.0);
  // A rigid body pushed at a corner.
  const RigidBodyModel body = RigidBodyModel::solid_box(0.2, {0.05, 0.05, 0.05});
  RigidBodyState body_state;
  std::vector<DeformationContact> contacts(3);
  // Jaws closing and opening across the duct's middle (grasping tissue: the anchored step).
  DuctGraspState duct_grasp;
  JawFrame duct_jaws;
  duct_jaws.hinge_W = Eigen::Vector3d(0.015, 0.0, 0.5 * duct.length_m);
  duct_jaws.rotation_WJ << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  int64_t duct_grasps = 0;
  int64_t catheter_grasps = 0;

  int64_t allocations = 0;
  {
    const test::AllocationCounter counter;
    for (int step = 0; step < 1000; ++step) {
      const int k = step % 4;  // 0..3 contacts, so vertices return to rest too
      for (int c = 0; c < k; ++c) {
        const int32_t f = (step * 37 + c * 101) % db.face_count();
        const auto& fv = db.face_vertices(f);
        contacts[c].face = f;
        contacts[c].point_O = db.position(fv[0]);
        contacts[c].penetration_O = -0.003 * db.face_normal(f);
      }
      EXPECT_TRUE(
          deform(local, {contacts.data(), static_cast<size_t>(std::min(k, 3))}, &local_state));
      if (step % 2 == 0) {
        db.set_positions(local_state.positions, local_state.changed);
      } else {
        db.set_positions(local_state.positions, local_state.changed, &scratch);
      }
      apply_node_force(&duct_state, 5 * duct.around + 3, Eigen::Vector3d(0.0, -0.01, 0.0));
      duct_jaws.opening_rad = 0.5 + 0.4 * std::sin(0.03 * step);
      clear_node_anchors(&duct_state);
      duct_grasps += update_duct_grasp({}, duct_jaws, Eigen::Isometry3d::Identity(),
                                       shell.mesh.nodes, duct_model, &duct_state, &duct_grasp)
                             .grasped_now
                         ? 1
                         : 0;
      (void)duct_coupling({}, {duct_jaws, duct_jaws, 0.001, 0.0}, Eigen::Isometry3d::Identity(),
                          shell.mesh.nodes, duct_grasp);
      EXPECT_TRUE(step_modal_shell(duct_model, &duct_state, 0.005));

      cath.external_force[40] = Eigen::Vector3d(0.0, 0.01 * std::sin(0.01 * step), 0.0);
      jaws.opening_rad = 0.5 + 0.4 * std::sin(0.02 * step);
      // Over particle 21 while open (the tool follows the catheter), still while closed.
      if (jaws.opening_rad > 0.45) jaws.hinge_W = cath.positions[21] + Eigen::Vector3d(0, 0.01, 0);
      clear_anchors(&cath);
      catheter_grasps += update_grasp({}, jaws, catheter, &cath, &grasp, 0.005).grasped_now ? 1 : 0;
      (void)coupling_wrench({}, {jaws, jaws, 0.001, 0.002}, catheter,
                            {cath.positions, cath.velocities}, grasp);
      clear_contacts(&cath);
      const int32_t n = update_surface_contacts(block, block_pose, {}, &tracking, &cath, reactions);
      EXPECT_TRUE(step_catheter(catheter, &cath, 0.005));
      finish_grasp_step(cath, &grasp);
      settle_reactions(cath, {reactions.data(), static_cast<size_t>(n)});

      apply_force_at(body, &body_state, Eigen::Vector3d(0.1, 0.0, 0.0),
                     body_state.pose_WB * Eigen::Vector3d(0.025, 0.025, 0.0));
      EXPECT_TRUE(step_rigid_body(body, &body_state, 0.005));
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(cath.guard_refinements, 0);  // the guard's path was exercised too
  EXPECT_GT(duct_grasps, 2);             // and the duct's anchored step
  EXPECT_GT(catheter_grasps, 2);         // and the catheter's grasp
  std::printf("[ models ] steps split by the catheter's guard: %lld\n",
              static_cast<long long>(cath.guard_refinements));
}

}  // namespace
}  // namespace lap::models
