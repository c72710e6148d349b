// Randomized property test of the segment proxy (issue 4): 10^6 ticks of random tool motion
// (translation up to 1 mm and rotation up to 1° per tick) around the real organ meshes of
// ../shared/meshes, which are concave. Invariants:
//  - forces and torques are finite;
//  - the ideal probe never crosses the surface (checked every tick through the face tree) and
//    its tip is never inside (parity, every 16th tick); any crossing is re-measured by the
//    brute-force reference, which must find no penetration deeper than 1e-9 m;
//  - every 1000th tick the brute-force reference (exhaustive, no tree) checks the ideal probe
//    too, and says whether the virtual probe penetrates: disagreements between "the proxy
//    pushes" and "the virtual probe is inside" are counted and reported (they are expected
//    where the ideal probe's history differs from a memoryless answer, e.g. a probe pushed
//    through a thin part keeps being pushed back the way it came).
// Counts are printed for the closing note.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "haptics/segment_proxy.h"
#include "haptics/setup/mesh_repair.h"
#include "sim/setup/mesh_loader.h"
#include "tests/support/brute_force_reference.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

constexpr int64_t kScale = test::kSanitizerDivisor;

struct Counts {
  int64_t ticks = 0;
  int64_t contact_ticks = 0;
  int64_t non_finite = 0;
  int64_t ideal_crossings = 0;     // tree check: the ideal segment crosses a face
  int64_t ideal_penetrations = 0;  // brute force: deeper than 1e-9 m inside
  int64_t tip_inside_checked = 0;
  int64_t tip_inside = 0;
  int64_t reference_samples = 0;
  int64_t reference_ideal_inside = 0;
  int64_t disagreements = 0;  // proxy pushes xor the virtual probe penetrates
  int64_t placement_limit_hits = 0;
  int64_t faults = 0;
};

bool inside_by_tree(const MeshDatabase& db, const Eigen::Vector3d& p, double reach) {
  const Eigen::Vector3d dir =
      Eigen::Vector3d(0.2718281828, 0.5772156649, 0.7071067812).normalized();
  const Eigen::Vector3d far = p + dir * reach;
  Eigen::Vector3d start = p;
  int count = 0;
  for (int i = 0; i < 10000; ++i) {
    const MeshDatabase::Crossing c = db.first_crossing(start, far, true);
    if (c.face < 0) break;
    ++count;
    start = start + c.t * (far - start) + dir * 1e-9;
  }
  return count % 2 == 1;
}

Counts run_mesh(const TriangleMesh& mesh, int64_t ticks, uint32_t seed) {
  Counts c;
  const MeshDatabase db = MeshDatabase::build(mesh);
  const SegmentDatabase sd = SegmentDatabase::build(db);
  HapticObject object;
  object.mesh = &db;
  object.segments = &sd;
  object.law.stiffness_n_per_m = 800.0;
  object.law.max_force_n = 8.0;
  const std::span<const HapticObject> objects(&object, 1);
  Eigen::AlignedBox3d box;
  for (int32_t v = 0; v < db.vertex_count(); ++v) box.extend(db.position(v));
  const double reach = 4.0 * box.diagonal().norm() + 1.0;

  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_int_distribution<int32_t> pick(0, db.vertex_count() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double length = 0.08;  // the probe: 8 cm of instrument shaft ending at the tip
  const double dt = 0.001;
  const double max_step = 0.001;               // 1 mm per tick
  const double max_turn = 1.0 * M_PI / 180.0;  // 1° per tick

  // The tip is pulled towards an anchor near a random surface point (6 mm out to 4 mm in), the
  // shaft direction towards a random direction in the outward hemisphere; both with noise.
  auto new_anchor = [&](Eigen::Vector3d* anchor, Eigen::Vector3d* aim) {
    const int32_t v = pick(rng);
    *anchor = db.position(v) + db.vertex_normal(v) * (0.006 - 0.010 * unit(rng));
    Eigen::Vector3d r(gauss(rng), gauss(rng), gauss(rng));
    if (r.dot(db.vertex_normal(v)) < 0.0) r = -r;
    *aim = (db.vertex_normal(v) + r.normalized()).normalized();
  };
  Eigen::Vector3d anchor;
  Eigen::Vector3d aim;
  new_anchor(&anchor, &aim);
  // Start free: a tip 1-3 cm out along a vertex normal whose probe touches nothing.
  Eigen::Vector3d tip;
  Eigen::Vector3d dir;
  for (int attempt = 0;; ++attempt) {
    const int32_t v = pick(rng);
    dir = db.vertex_normal(v);
    tip = db.position(v) + dir * (0.01 + 0.02 * unit(rng));
    if (reference_segment_distance(db, tip, tip + length * dir).distance > 0.002 &&
        !reference_inside(db, tip)) {
      break;
    }
    EXPECT_LT(attempt, 1000);
  }
  Eigen::Vector3d vel = Eigen::Vector3d::Zero();
  SegmentProxy proxy;
  proxy.reset(tip, tip + length * dir);
  for (int64_t tick = 0; tick < ticks; ++tick) {
    if (tick % 400 == 0) new_anchor(&anchor, &aim);
    const Eigen::Vector3d accel = 60.0 * (anchor - tip) - 8.0 * vel +
                                  Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)) * 3.0;
    vel += accel * dt;
    Eigen::Vector3d step = vel * dt;
    if (step.norm() > max_step) {
      step *= max_step / step.norm();
      vel = step / dt;
    }
    tip += step;
    // Turn towards the aim (plus noise) by at most 1°.
    Eigen::Vector3d axis =
        dir.cross(aim) * 2.0 + Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)) * 0.3;
    double angle = std::min(axis.norm() * 0.02, max_turn);
    if (axis.norm() > 0.0 && angle > 0.0) {
      dir = (Eigen::AngleAxisd(angle, axis.normalized()) * dir).normalized();
    }
    const Eigen::Vector3d tail = tip + length * dir;
    const SegmentProxyOutput out = proxy.step(objects, tip, tail, dt);
    ++c.ticks;
    if (!out.force_W.allFinite() || !out.torque_W.allFinite() || !out.force_a_W.allFinite()) {
      ++c.non_finite;
    }
    const bool pushes = out.force_W.norm() > 0.0;
    c.contact_ticks += out.contact_count > 0 ? 1 : 0;
    // Every tick: does the ideal segment cross the surface (tree, both sides)?
    if (db.first_crossing(out.ideal_a_W, out.ideal_b_W, true).face >= 0) {
      ++c.ideal_crossings;
      if (reference_segment_penetrates(db, out.ideal_a_W, out.ideal_b_W, 1e-9)) {
        ++c.ideal_penetrations;
      }
    }
    if (tick % 16 == 0) {
      ++c.tip_inside_checked;
      if (inside_by_tree(db, out.ideal_a_W, reach) &&
          reference_segment_penetrates(db, out.ideal_a_W, out.ideal_a_W, 1e-9)) {
        ++c.tip_inside;
      }
    }
    if (tick % 1000 == 0) {
      ++c.reference_samples;
      if (reference_segment_penetrates(db, out.ideal_a_W, out.ideal_b_W, 1e-9)) {
        ++c.reference_ideal_inside;
      }
      const bool virtual_inside =
          reference_segment_distance(db, tip, tail).distance == 0.0 || reference_inside(db, tip);
      if (pushes != virtual_inside) ++c.disagreements;
    }
  }
  c.placement_limit_hits = proxy.stats().placement_limit_hits;
  c.faults = proxy.stats().faults;
  return c;
}

TEST(SegmentProxyRandom, RealOrganMeshes) {
  LAP_REQUIRE_SHARED_MESHES();
  const std::pair<const char*, bool> files[] = {{"liver_openhelp.stl", false},
                                                {"stomach_openhelp.stl", false},
                                                {"duodenum_openhelp.stl", false},
                                                {"gallbladder_sofaenv_glt.stl", false},
                                                {"liver_sofaenv_glt.stl", true}};
  int64_t total = 0;
  uint32_t seed = 400;
  for (const auto& [file, repair] : files) {
    TriangleMesh mesh = sim::load_mesh(test::shared_meshes_dir() / file, {0.001, 0.0}).value();
    if (repair) repair_mesh(mesh);
    const Counts c = run_mesh(mesh, 200000 / kScale, seed++);
    std::printf(
        "%-28s %7d tris: %lld ticks, %lld in contact, ideal crossings %lld (brute-force "
        "penetrations %lld), tip inside %lld/%lld, reference samples %lld (ideal inside %lld, "
        "disagreements %lld), placement limit %lld, non-finite %lld, faults %lld\n",
        file, mesh.triangle_count(), static_cast<long long>(c.ticks),
        static_cast<long long>(c.contact_ticks), static_cast<long long>(c.ideal_crossings),
        static_cast<long long>(c.ideal_penetrations), static_cast<long long>(c.tip_inside),
        static_cast<long long>(c.tip_inside_checked), static_cast<long long>(c.reference_samples),
        static_cast<long long>(c.reference_ideal_inside), static_cast<long long>(c.disagreements),
        static_cast<long long>(c.placement_limit_hits), static_cast<long long>(c.non_finite),
        static_cast<long long>(c.faults));
    EXPECT_EQ(c.non_finite, 0) << file;
    EXPECT_EQ(c.faults, 0) << file;
    EXPECT_EQ(c.ideal_penetrations, 0) << file;
    EXPECT_EQ(c.tip_inside, 0) << file;
    EXPECT_EQ(c.reference_ideal_inside, 0) << file;
    EXPECT_GT(c.contact_ticks, c.ticks / 10) << file;  // the motion does reach the organ
    total += c.ticks;
  }
  std::printf("real meshes: %lld ticks\n", static_cast<long long>(total));
}

}  // namespace
}  // namespace lap::haptics
