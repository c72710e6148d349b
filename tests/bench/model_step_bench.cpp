// BM_ModelStep (issue 6): one step of the session's modelling thread over the OpenHELP liver,
// stomach and duodenum (the generated stand-ins where those meshes are absent; the label says
// which) under local deformation and the stand-in duct as the modal shell, with the 64-particle
// catheter lying on the liver (its contacts), grasped by one tool's jaws, the other tool pressing
// into each organ. The step is the tissue world's (sim::TissueWorld: grasps, contacts, catheter,
// dents, duct modes), its deformations published, and the proxies' next copy of the surfaces taking
// them up (sim::HapticSurfaces: normals, face and edge trees refitted where the surfaces moved, the
// liver's force-shading normals) — everything the session's modelling thread does per tick. Target:
// median <= 200 us. The two parts are also timed apart in the same run (world_median_ns,
// takeup_median_ns). BM_ModelStepSlidingDent: the same with tool 0's dent moving every tick.

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/shading_normals.h"
#include "models/catheter_model.h"
#include "models/local_deformation.h"
#include "models/modal_shell.h"
#include "sim/runtime/haptic_surfaces.h"
#include "sim/runtime/tissue_world.h"
#include "tests/bench/bench_support.h"

namespace lap::bench {
namespace {

// ticks_per_face: how long tool 0's dent stays on one face before it moves to the next.
void model_step(benchmark::State& state, int64_t ticks_per_face) {
  // The scene: the three organs under local deformation and the stand-in duct as the
  // modal shell, exactly as the session's modelling loop builds them (sim::TissueWorld).
  sim::Scene scene;
  const OrganSet& organs = organ_set();
  for (const haptics::TriangleMesh& mesh : organs.meshes) {
    sim::Organ o;
    o.name = "organ_" + std::to_string(scene.organs.size());
    o.mesh = mesh;
    o.model = models::ModelKind::kLocal;
    o.material.stiffness_n_per_m = 300.0;
    o.material.damping_n_s_per_m = 0.5;
    scene.organs.push_back(std::move(o));
  }
  state.SetLabel(organs.label);
  const Eigen::AlignedBox3d liver = [&] {
    Eigen::AlignedBox3d b;
    for (const Eigen::Vector3d& p : scene.organs[0].mesh.positions) b.extend(p);
    return b;
  }();
  sim::Organ duct;
  duct.name = "duct";
  duct.mesh = haptics::make_stand_in_cystic_duct();
  duct.model = models::ModelKind::kModalShell;
  duct.material.stiffness_n_per_m = 150.0;
  scene.organs.push_back(std::move(duct));
  sim::TissueWorldSettings ws;  // the default 64-particle catheter, with gravity
  ws.catheter.gravity_m_per_s2 = Eigen::Vector3d(0.0, -9.81, 0.0);
  // Laid across the liver's top, 1 mm into it: its particles there are in contact.
  ws.catheter_start_W =
      Eigen::Vector3d(liver.min().x(), liver.max().y() - 0.001, liver.center().z());
  ws.catheter_direction_W = Eigen::Vector3d::UnitX();
  std::unique_ptr<sim::TissueWorld> world = sim::TissueWorld::build(scene, ws, nullptr).value();
  // The proxies' copy of the surfaces (sim::HapticSurfaces), as the session builds it; the liver
  // force-shaded as in the default scenario (crease 40 degrees).
  std::vector<std::unique_ptr<haptics::MeshDatabase>> dbs;
  std::vector<std::unique_ptr<haptics::SegmentDatabase>> segments;
  std::vector<const haptics::MeshDatabase*> db_ptrs;
  std::vector<const haptics::SegmentDatabase*> segment_ptrs;
  for (int32_t i = 0; i < world->organ_count(); ++i) {
    dbs.push_back(
        std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(world->surface(i))));
    segments.push_back(
        std::make_unique<haptics::SegmentDatabase>(haptics::SegmentDatabase::build(*dbs.back())));
    db_ptrs.push_back(dbs.back().get());
    segment_ptrs.push_back(segments.back().get());
  }
  const haptics::ShadingNormals liver_shading =
      haptics::ShadingNormals::build(*dbs[0], 40.0 * 3.14159265358979323846 / 180.0);
  std::vector<const haptics::ShadingNormals*> shading(dbs.size(), nullptr);
  shading[0] = &liver_shading;
  sim::HapticSurfaces surfaces(db_ptrs, segment_ptrs, shading);
  std::vector<sim::SurfaceDeformation> published = world->make_deformations();

  // Tool 0 presses 0.5-1.5 N into each of the three organs at a point sliding across its faces;
  // tool 1's jaws close on the catheter's particle 40 and hold it.
  std::array<sim::ToolModelInput, 2> tools{};
  tools[0].valid = true;
  tools[0].jaws.hinge_W = Eigen::Vector3d(1.0, 1.0, 1.0);  // far away: no grasp
  tools[1].valid = true;
  const Eigen::Vector3d held = world->catheter().positions[40];
  tools[1].jaws.hinge_W = held + Eigen::Vector3d(0.0, 0.01, 0.0);  // jaws pointing down at it
  tools[1].jaws.rotation_WJ.col(0) = Eigen::Vector3d::UnitX();
  tools[1].jaws.rotation_WJ.col(1) = Eigen::Vector3d::UnitY();
  tools[1].jaws.rotation_WJ.col(2) = Eigen::Vector3d::UnitZ();
  tools[1].jaws.opening_rad = 0.1;
  const double dt = 0.005;  // 200 Hz
  int64_t tick = 0;
  StepTimer world_timer;
  StepTimer takeup_timer;
  auto step = [&]() {
    const double s = static_cast<double>(tick++);
    tools[0].contact_count = 0;
    for (int32_t k = 0; k < 3; ++k) {
      const haptics::MeshDatabase& db = *dbs[static_cast<size_t>(k)];
      const int32_t f =
          (db.face_count() / 3 + static_cast<int32_t>(tick / ticks_per_face)) % db.face_count();
      const auto& fv = db.face_vertices(f);
      sim::ToolContact& c = tools[0].contacts[static_cast<size_t>(tools[0].contact_count++)];
      c.organ = k;
      c.primitive = {haptics::PrimitiveKind::kFace, f};
      c.point_W = (db.position(fv[0]) + db.position(fv[1]) + db.position(fv[2])) / 3.0;
      c.force_on_organ_W = -(1.0 + 0.5 * std::sin(0.05 * s)) * db.face_normal(f);
    }
    world_timer.start();
    world->step(tools, dt);
    world->write_deformations(&published);
    world_timer.stop();
    takeup_timer.start();
    surfaces.take_up(published, tick);
    takeup_timer.stop();
  };
  for (int i = 0; i < 200; ++i) step();
  world_timer = StepTimer();
  takeup_timer = StepTimer();
  StepTimer total_timer;
  int64_t published_vertices = 0;
  for (auto _ : state) {
    total_timer.start();
    step();
    total_timer.stop();
    for (const sim::SurfaceDeformation& d : published) published_vertices += d.count;
  }
  total_timer.report(state);
  world_timer.report(state, "world_");
  takeup_timer.report(state, "takeup_");
  state.counters["displaced_vertices"] =
      static_cast<double>(published_vertices) / static_cast<double>(state.iterations());
  int64_t triangles = 0;
  for (int32_t k = 0; k < 3; ++k) triangles += dbs[static_cast<size_t>(k)]->face_count();
  state.counters["organ_triangles"] = static_cast<double>(triangles);
  state.counters["duct_triangles"] = static_cast<double>(dbs.back()->face_count());
  state.counters["catheter_particles"] = world->catheter_model().particle_count();
  state.counters["catheter_contacts"] = world->catheter_contacts();
  state.counters["catheter_grasped"] = world->catheter_grasps()[1].grasping() ? 1.0 : 0.0;
  state.counters["guard_splits"] = static_cast<double>(world->catheter().guard_refinements);
}
// The dent held on each face for 20 ticks (0.1 s) while its depth changes every tick: the
// moved vertices are the same list from one tick to the next most of the time (a tool held
// still), and the take-up reuses the region it found for them.
void BM_ModelStep(benchmark::State& state) { model_step(state, 20); }
BENCHMARK(BM_ModelStep)->Iterations(2000);

// The dent on a new face every tick (a tool sliding across the organ): the moved list changes
// every tick, and the take-up finds its region afresh each time.
void BM_ModelStepSlidingDent(benchmark::State& state) { model_step(state, 1); }
BENCHMARK(BM_ModelStepSlidingDent)->Iterations(2000);

}  // namespace
}  // namespace lap::bench
