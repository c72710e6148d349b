// BM_ModelStep (issue 6): one modelling step of the default duct (modal shell), a 64-particle
// catheter, and the OpenHELP liver, stomach and duodenum under local deformation, each organ with
// a moving contact and its database updated for the proxies. Target: median <= 200 us.

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "haptics/mesh_database.h"
#include "models/catheter_model.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

void BM_ModelStep(benchmark::State& state) {
  std::vector<std::unique_ptr<haptics::MeshDatabase>> organs;
  for (const haptics::TriangleMesh& mesh : openhelp_organs()) {
    organs.push_back(std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(mesh)));
  }
  if (organs.empty()) {
    state.SkipWithError("the OpenHELP meshes are not in ../shared/meshes");
    return;
  }
  std::vector<models::LocalDeformationModel> local;
  std::vector<models::LocalDeformationState> local_state;
  std::vector<haptics::MeshUpdateScratch> scratch;
  for (const auto& db : organs) {
    local.push_back(models::LocalDeformationModel::build(*db, {}));
    local_state.emplace_back(local.back());
    scratch.emplace_back(*db);
  }
  const models::DuctSettings duct;
  const models::DuctShell shell = models::make_duct_shell(duct);
  const models::ModalShellModel duct_model = models::ModalShellModel::build(
      shell.mesh, shell.held_dof, models::default_duct_modal_settings(duct));
  models::ModalShellState duct_state(duct_model);
  models::CatheterSettings cs;
  cs.gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  const models::CatheterModel catheter = models::CatheterModel::build(cs);
  models::CatheterState cath(catheter, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
  cath.fixed[0] = cath.fixed[1] = 1;  // held by a grasper

  const double dt = 0.005;  // 200 Hz
  int64_t tick = 0;
  std::vector<int32_t> contact_face(organs.size());
  for (size_t k = 0; k < organs.size(); ++k) contact_face[k] = organs[k]->face_count() / 3;
  auto step = [&]() {
    const double s = static_cast<double>(tick++);
    for (size_t k = 0; k < organs.size(); ++k) {
      // A tool pressing 3-5 mm into each organ, sliding across faces.
      const int32_t f =
          (contact_face[k] + static_cast<int32_t>(tick / 20)) % organs[k]->face_count();
      const auto& fv = organs[k]->face_vertices(f);
      models::DeformationContact c;
      c.face = f;
      c.point_O = local[k].rest_position(fv[0]);
      c.penetration_O = -(0.004 + 0.001 * std::sin(0.05 * s)) * organs[k]->face_normal(f);
      models::deform(local[k], {&c, 1}, &local_state[k]);
      organs[k]->set_positions(local_state[k].positions, local_state[k].changed, &scratch[k]);
    }
    models::apply_node_force(&duct_state, duct.along / 2 * duct.around + duct.around / 4,
                             Eigen::Vector3d(0.0, -0.01 * (1.0 + std::sin(0.03 * s)), 0.0));
    models::step_modal_shell(duct_model, &duct_state, dt);
    cath.external_force[40] = Eigen::Vector3d(0.0, 0.002 * std::sin(0.02 * s), 0.0);
    models::step_catheter(catheter, &cath, dt);
  };
  for (int i = 0; i < 200; ++i) step();
  StepTimer timer;
  for (auto _ : state) {
    timer.start();
    step();
    timer.stop();
  }
  timer.report(state);
  int64_t triangles = 0;
  for (const auto& db : organs) triangles += db->face_count();
  state.counters["organ_triangles"] = static_cast<double>(triangles);
  state.counters["duct_nodes"] = static_cast<double>(duct_model.node_count());
  state.counters["duct_modes"] = duct_model.mode_count();
  state.counters["catheter_particles"] = catheter.particle_count();
  state.counters["guard_splits"] = static_cast<double>(cath.guard_refinements);
}
BENCHMARK(BM_ModelStep)->Iterations(2000);

}  // namespace
}  // namespace lap::bench
