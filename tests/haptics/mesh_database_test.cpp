#include "haptics/mesh_database.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>

#include "haptics/closest_point.h"
#include "haptics/corner_angle.h"
#include "haptics/segment_database.h"
#include "haptics/segment_triangle.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/setup/mesh_repair.h"
#include "tests/support/brute_force_reference.h"

namespace lap::haptics {
namespace {

// The unit normal of face f from its vertices' current positions (MeshDatabase's formula).
Eigen::Vector3d face_normal_now(const MeshDatabase& db, int32_t f) {
  const auto& t = db.face_vertices(f);
  const Eigen::Vector3d n =
      (db.position(t[1]) - db.position(t[0])).cross(db.position(t[2]) - db.position(t[0]));
  return n / n.norm();
}

TEST(MeshDatabase, NeighbourListsOfAClosedSphereAreConsistent) {
  const TriangleMesh s = make_uv_sphere(0.05, 12, 24);
  const MeshDatabase db = MeshDatabase::build(s);
  EXPECT_EQ(db.face_count(), s.triangle_count());
  EXPECT_EQ(db.vertex_count(), s.vertex_count());
  EXPECT_EQ(db.edge_count(), s.triangle_count() * 3 / 2);
  EXPECT_FALSE(db.has_boundary());
  for (int32_t f = 0; f < db.face_count(); ++f) {
    // Figure 4-2(c): three vertices, three edges; edge k joins corners k and k+1.
    const auto& v = db.face_vertices(f);
    const auto& e = db.face_edges(f);
    for (int k = 0; k < 3; ++k) {
      const auto& ev = db.edge_vertices(e[k]);
      EXPECT_EQ(std::set<int32_t>({ev[0], ev[1]}), std::set<int32_t>({v[k], v[(k + 1) % 3]}));
      const auto& ef = db.edge_faces(e[k]);
      EXPECT_TRUE(ef[0] == f || ef[1] == f);
    }
    // Faces are stored in tree order; original_face maps back to the input mesh.
    EXPECT_EQ(std::set<int32_t>(v.begin(), v.end()),
              std::set<int32_t>(s.triangles[db.original_face(f)].begin(),
                                s.triangles[db.original_face(f)].end()));
  }
  for (int32_t e = 0; e < db.edge_count(); ++e) EXPECT_GE(db.edge_faces(e)[1], 0);  // Figure 4-2(b)
  for (int32_t v = 0; v < db.vertex_count(); ++v) {
    int faces = 0;
    db.for_each_vertex_face(v, [&](int32_t f) {
      const auto& fv = db.face_vertices(f);
      EXPECT_TRUE(fv[0] == v || fv[1] == v || fv[2] == v);
      ++faces;
    });
    int expected = 0;
    for (const auto& t : s.triangles) expected += (t[0] == v || t[1] == v || t[2] == v) ? 1 : 0;
    EXPECT_EQ(faces, expected) << "vertex " << v;
  }
}

TEST(MeshDatabase, NormalsOfACube) {
  const MeshDatabase db = MeshDatabase::build(make_box(Eigen::Vector3d(1, 1, 1), 1));
  for (int32_t v = 0; v < db.vertex_count(); ++v) {
    // Angle-weighted: a cube corner's normal is the diagonal whatever the triangulation.
    EXPECT_NEAR(db.vertex_normal(v).dot(db.position(v).cwiseSign().normalized()), 1.0, 1e-12);
  }
  for (int32_t e = 0; e < db.edge_count(); ++e) {
    const Eigen::Vector3d mid =
        0.5 * (db.position(db.edge_vertices(e)[0]) + db.position(db.edge_vertices(e)[1]));
    const Eigen::Vector3d n = db.edge_normal(e);
    // Cube edges bisect their two faces; the face diagonals lie flat (normal = face normal).
    const int nonzero =
        (std::abs(mid.x()) > 0.25) + (std::abs(mid.y()) > 0.25) + (std::abs(mid.z()) > 0.25);
    if (nonzero == 2) {
      EXPECT_NEAR(n.norm(), 1.0, 1e-12);
      EXPECT_NEAR(n.dot(mid.normalized()), 1.0, 1e-12);
    }
  }
}

TEST(MeshDatabase, OpenPlateHasBoundaryEdgesWithOneFace) {
  const MeshDatabase db = MeshDatabase::build(make_plate(0.1, 3));
  EXPECT_TRUE(db.has_boundary());
  int boundary = 0;
  for (int32_t e = 0; e < db.edge_count(); ++e) boundary += db.edge_faces(e)[1] < 0 ? 1 : 0;
  EXPECT_EQ(boundary, 12);
}

TEST(MeshDatabase, NonManifoldEdgeIsRefusedWithItsName) {
  TriangleMesh m = make_box(Eigen::Vector3d(1, 1, 1), 1);
  const Triangle t0 = m.triangles[0];
  m.positions.push_back(Eigen::Vector3d(3, 3, 3));
  m.triangles.push_back({t0[1], t0[0], m.vertex_count() - 1});  // a fin wound as a twin
  try {
    (void)MeshDatabase::build(m);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("has more than two faces"), std::string::npos) << e.what();
  }
}

TEST(MeshDatabase, InconsistentOrientationIsRefused) {
  TriangleMesh m = make_box(Eigen::Vector3d(1, 1, 1), 1);
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  EXPECT_THROW((void)MeshDatabase::build(m), std::invalid_argument);
}

TEST(MeshDatabase, PinchedVertexIsRefused) {
  TriangleMesh a = make_box(Eigen::Vector3d(1, 1, 1), 1);
  TriangleMesh b = make_box(Eigen::Vector3d(1, 1, 1), 1);
  b.transform(Eigen::Affine3d(Eigen::Translation3d(1, 1, 1)));
  a.append(b);
  // Merge the touching corners (0.5, 0.5, 0.5) of the two boxes into one vertex.
  int32_t keep = -1;
  for (int32_t v = 0; v < a.vertex_count(); ++v) {
    if ((a.positions[v] - Eigen::Vector3d(0.5, 0.5, 0.5)).norm() < 1e-12) {
      if (keep < 0) keep = v;
      for (auto& t : a.triangles) {
        for (int32_t& x : t) x = x == v ? keep : x;
      }
    }
  }
  ASSERT_EQ(remove_unreferenced_vertices(a), 1);
  try {
    (void)MeshDatabase::build(a);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is non-manifold"), std::string::npos) << e.what();
  }
}

TEST(BoundingVolumeTree, FirstHitMatchesExhaustiveSearchOnRandomSegments) {
  const MeshDatabase db = MeshDatabase::build(make_uv_sphere(0.05, 40, 80));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.07, 0.07);
  int hits = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p0(u(rng), u(rng), u(rng));
    // Short paths (a tick) and long ones (a jump across the object).
    const Eigen::Vector3d p1 =
        i % 2 == 0 ? Eigen::Vector3d(p0 + Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.05)
                   : Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (bool two_sided : {false, true}) {
      const MeshDatabase::Crossing c = db.first_crossing(p0, p1, two_sided);
      const ReferenceCrossing r = reference_first_crossing(db, p0, p1, two_sided);
      ASSERT_EQ(c.face >= 0, r.face >= 0) << "segment " << i;
      if (c.face >= 0) {
        EXPECT_DOUBLE_EQ(c.t, r.t);
        EXPECT_EQ(c.from_front, r.from_front);
        ++hits;
      }
    }
  }
  EXPECT_GT(hits, 1000);
}

TEST(BoundingVolumeTree, SubMicrometreTrianglesFarFromTheOriginAreHit) {
  // Float boxes are rounded outward: a 0.1 micrometre triangle 0.3 m from the origin (where a
  // float step is 3e-8 m) is still found.
  TriangleMesh m = make_uv_sphere(1e-7, 6, 12);
  m.transform(Eigen::Affine3d(Eigen::Translation3d(0.3, -0.2, 0.25)));
  const MeshDatabase db = MeshDatabase::build(m);
  const Eigen::Vector3d c(0.3, -0.2, 0.25);
  const Eigen::Vector3d p0 = c + Eigen::Vector3d(3e-7, 1e-8, 0);
  const Eigen::Vector3d p1 = c - Eigen::Vector3d(0, 0, 0) + Eigen::Vector3d(1e-9, 2e-9, 0);
  const MeshDatabase::Crossing hit = db.first_crossing(p0, p1, false);
  ASSERT_GE(hit.face, 0);
  const ReferenceCrossing r = reference_first_crossing(db, p0, p1, false);
  ASSERT_GE(r.face, 0);
  EXPECT_DOUBLE_EQ(hit.t, r.t);  // the path may pass through an edge: same t, either face
}

TEST(BoundingVolumeTree, RefitAfterDeformationAnswersLikeARebuild) {
  TriangleMesh m = make_uv_sphere(0.05, 30, 60);
  MeshDatabase db = MeshDatabase::build(m);
  // Deform every vertex (a wobble), then refit; compare with a database built from scratch.
  std::vector<Eigen::Vector3d> moved(m.positions.size());
  for (size_t i = 0; i < moved.size(); ++i) {
    const Eigen::Vector3d& p = m.positions[i];
    moved[i] = p * (1.0 + 0.3 * std::sin(40.0 * p.x()) * std::cos(30.0 * p.y())) +
               Eigen::Vector3d(0.01, 0, 0);
  }
  db.set_positions(moved);
  TriangleMesh m2 = m;
  m2.positions = moved;
  const MeshDatabase fresh = MeshDatabase::build(m2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p0(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p1(u(rng), u(rng), u(rng));
    auto query = [&](const MeshDatabase& d) {
      const MeshDatabase::Crossing c = d.first_crossing(p0, p1, false);
      return c.face >= 0 ? c.t : -1.0;
    };
    EXPECT_DOUBLE_EQ(query(db), query(fresh)) << i;
  }
  // Normals followed the deformation.
  for (int32_t v = 0; v < db.vertex_count(); v += 37)
    EXPECT_TRUE(db.vertex_normal(v).isApprox(fresh.vertex_normal(v), 1e-12));
  // The stored face normals too, bit for bit.
  for (int32_t f = 0; f < db.face_count(); ++f)
    ASSERT_EQ(db.face_normal(f), face_normal_now(db, f));
}

// A local deformation (§6.5) through the workspace touches each face, vertex and tree node once,
// and must leave what the full update leaves: positions, face normals and vertex normals bit for
// bit (the plain local update, which walks fans, to rounding), and tree boxes equal to a full
// refit's, also after the database moved by another route in between; the segment database's edge
// tree, refitted from the moved faces alone, equal to its full refit too. A closed mesh, and an
// open one (its rim vertices' fans end at the boundary).
TEST(MeshDatabase, LocalUpdateWithScratchEqualsTheFullUpdate) {
  for (const TriangleMesh& m : {make_uv_sphere(0.05, 40, 80), make_bowl(0.05, 20, 80)}) {
    MeshDatabase local = MeshDatabase::build(m);
    MeshDatabase plain = MeshDatabase::build(m);
    MeshDatabase full = MeshDatabase::build(m);
    MeshUpdateScratch scratch(local);
    SegmentDatabase local_edges = SegmentDatabase::build(local);
    SegmentDatabase plain_edges = SegmentDatabase::build(plain);
    SegmentUpdateScratch edge_scratch(local_edges);
    ASSERT_GT(local_edges.contactable_edge_count(), 0);
    std::vector<Eigen::Vector3d> positions = m.positions;
    std::mt19937 rng(2);
    std::uniform_int_distribution<int32_t> pick(0, local.vertex_count() - 1);
    std::vector<int32_t> moved;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int round = 0; round < 40; ++round) {
      if (round % 4 != 3) {
        // Dent a patch around a random vertex (and let the last patch spring back).
        centre = m.positions[pick(rng)];
        moved.clear();
      }
      // Every fourth round holds the last dent at another depth: the same moved list again,
      // which reuses the region found for it.
      const double depth = round % 4 == 3 ? 0.1 : 0.2;
      for (int32_t v = 0; v < local.vertex_count(); ++v) {
        const double d = (m.positions[v] - centre).norm();
        const bool was = positions[v] != m.positions[v];
        positions[v] =
            d < 0.015 ? m.positions[v] * (1.0 - depth * (0.015 - d) / 0.015) : m.positions[v];
        if (round % 4 != 3 && (was || d < 0.015)) moved.push_back(v);
      }
      if (round % 10 == 5) {
        // Now and then by another route: the workspace's cached angles go stale and must be
        // noticed (the next rounds would leave the rim's normals wrong otherwise).
        local.set_positions(positions);
        local_edges.refit_edge_tree();
      } else {
        local.set_positions(positions, moved, &scratch);
        local_edges.refit_moved_edges(scratch.moved, &edge_scratch);
      }
      plain.set_positions(positions, moved);
      full.set_positions(positions);
      plain_edges.refit_edge_tree();
      for (int32_t v = 0; v < local.vertex_count(); ++v) {
        // The same terms in the same order as the full update: equal bit for bit. The plain
        // local update walks fans (another order): equal to rounding.
        ASSERT_EQ(local.vertex_normal(v), full.vertex_normal(v)) << "round " << round << " v " << v;
        ASSERT_LT((plain.vertex_normal(v) - full.vertex_normal(v)).norm(), 1e-14)
            << "round " << round << " v " << v;
        ASSERT_EQ(local.position(v), plain.position(v));
      }
      // Stored face normals: both paths give the normal of the face as it now is, bit for bit.
      for (int32_t f = 0; f < local.face_count(); ++f) {
        ASSERT_EQ(local.face_normal(f), face_normal_now(local, f))
            << "round " << round << " f " << f;
        ASSERT_EQ(plain.face_normal(f), face_normal_now(plain, f))
            << "round " << round << " f " << f;
      }
      const auto& a = local.tree().nodes();
      const auto& b = plain.tree().nodes();
      ASSERT_EQ(a.size(), b.size());
      for (size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].lo, b[i].lo) << "round " << round << " node " << i;
        ASSERT_EQ(a[i].hi, b[i].hi) << "round " << round << " node " << i;
      }
      const auto& ea = local_edges.edge_tree().nodes();
      const auto& eb = plain_edges.edge_tree().nodes();
      ASSERT_EQ(ea.size(), eb.size());
      for (size_t i = 0; i < ea.size(); ++i) {
        ASSERT_EQ(ea[i].lo, eb[i].lo) << "round " << round << " edge node " << i;
        ASSERT_EQ(ea[i].hi, eb[i].hi) << "round " << round << " edge node " << i;
      }
      EXPECT_EQ(local.revision(), plain.revision());
    }
  }
}

// --- The incremental update against references recomputed from the positions alone ---

// The angle-weighted vertex normals (§4.2) of the database's current positions, brute force:
// every face in ascending order, its unit normal n / |n| and corner_angle() (corner_angle.h) at
// each corner one at a time, each share added to its vertex; the same formulas and order the
// database has, none of its update code.
std::vector<Eigen::Vector3d> reference_vertex_normals(const MeshDatabase& db) {
  std::vector<Eigen::Vector3d> sum(static_cast<size_t>(db.vertex_count()), Eigen::Vector3d::Zero());
  for (int32_t f = 0; f < db.face_count(); ++f) {
    const auto& t = db.face_vertices(f);
    const Eigen::Vector3d ab = db.position(t[1]) - db.position(t[0]);
    const Eigen::Vector3d ac = db.position(t[2]) - db.position(t[0]);
    const Eigen::Vector3d bc = db.position(t[2]) - db.position(t[1]);
    const Eigen::Vector3d n = ab.cross(ac);
    const double y = n.norm();
    if (!(y > 0.0)) continue;  // a degenerate face adds nothing
    const Eigen::Vector3d unit = n / y;
    const double angle_a = corner_angle(y, ab.dot(ac));
    const double angle_b = corner_angle(y, -ab.dot(bc));
    const double angles[3] = {angle_a, angle_b, 3.14159265358979323846 - angle_a - angle_b};
    for (int k = 0; k < 3; ++k) sum[static_cast<size_t>(t[k])] += angles[k] * unit;
  }
  for (Eigen::Vector3d& n : sum) {
    const double len = n.norm();
    n = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
  }
  return sum;
}

// Node i's box recomputed from its primitives' points (points(k, visit) visits primitive k's):
// a leaf's rounded outward by set_box(), an inner node's the union of its children's.
template <typename Points>
BvhNode reference_box(const BoundingVolumeTree& tree, size_t i, const Points& points) {
  const BvhNode& node = tree.nodes()[i];
  BvhNode box = node;
  if (node.count > 0) {
    Eigen::AlignedBox3d bounds;
    for (int32_t k = node.first; k < node.first + node.count; ++k) {
      points(k, [&](const Eigen::Vector3d& p) { bounds.extend(p); });
    }
    BoundingVolumeTree::set_box(box, bounds);
    return box;
  }
  const BvhNode a = reference_box(tree, i + 1, points);
  const BvhNode b = reference_box(tree, static_cast<size_t>(node.first), points);
  for (int c = 0; c < 3; ++c) {
    box.lo[c] = std::min(a.lo[c], b.lo[c]);
    box.hi[c] = std::max(a.hi[c], b.hi[c]);
  }
  return box;
}

// Every node of `tree` against reference_box(); false with the first difference in *why.
template <typename Points>
bool boxes_match(const BoundingVolumeTree& tree, const Points& points, std::string* why) {
  for (size_t i = 0; i < tree.nodes().size(); ++i) {
    const BvhNode want = reference_box(tree, i, points);
    if (tree.nodes()[i].lo != want.lo || tree.nodes()[i].hi != want.hi) {
      *why = "node " + std::to_string(i);
      return false;
    }
  }
  return true;
}

// What DeformedSurface (sim/runtime) passes as moved: the vertices displaced before (in their
// order), then those displaced now and not before.
std::vector<int32_t> moved_between(const std::vector<int32_t>& before,
                                   const std::vector<int32_t>& now) {
  std::vector<int32_t> moved = before;
  const std::set<int32_t> was(before.begin(), before.end());
  for (const int32_t v : now) {
    if (was.count(v) == 0) moved.push_back(v);
  }
  return moved;
}

// A random sequence of dents — sliding by a few millimetres, jumping elsewhere, held still at
// another depth, growing, two at once, released back to rest — taken up through the workspaces
// (MeshUpdateScratch, SegmentUpdateScratch), whose regions follow the moved vertices from step to
// step. After every step: positions as set, face normals the formula's bit for bit, vertex
// normals bit for bit those recomputed from the positions alone, every node box of the face and
// edge trees equal to one recomputed from its primitives, and the vertices listed as recomputed
// exactly the vertices of the faces with a moved vertex. On a closed sphere, an open bowl (fans
// ending at the boundary) and the stand-in liver.
TEST(MeshDatabase, IncrementalRegionOverMovingDentsEqualsARebuildFromThePositions) {
  for (const TriangleMesh& m :
       {make_uv_sphere(0.05, 40, 80), make_bowl(0.05, 20, 80), make_stand_in_liver()}) {
    MeshDatabase db = MeshDatabase::build(m);
    SegmentDatabase edges = SegmentDatabase::build(db);
    MeshUpdateScratch scratch(db);
    SegmentUpdateScratch edge_scratch(edges);
    const std::vector<Eigen::Vector3d>& rest = m.positions;
    std::vector<Eigen::Vector3d> positions = rest;
    std::mt19937 rng(7);
    std::uniform_int_distribution<int32_t> pick(0, db.vertex_count() - 1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::AlignedBox3d extent;
    for (const Eigen::Vector3d& p : rest) extent.extend(p);
    const double size = extent.diagonal().norm();
    std::vector<Eigen::Vector3d> centres = {rest[static_cast<size_t>(pick(rng))]};
    double radius = 0.2 * size;
    double depth = 0.1;
    std::vector<int32_t> displaced;
    for (int step = 0; step < 60; ++step) {
      switch (step % 7) {
        case 0:  // jump elsewhere
          centres = {rest[static_cast<size_t>(pick(rng))]};
          break;
        case 1:
        case 2:  // slide a little
          centres[0] += 0.02 * size * Eigen::Vector3d(u(rng), u(rng), u(rng));
          break;
        case 3:  // held still, another depth
          depth = 0.05 + 0.1 * std::abs(u(rng));
          break;
        case 4:  // grow or shrink
          radius = (0.1 + 0.15 * std::abs(u(rng))) * size;
          break;
        case 5:  // a second dent
          centres.push_back(rest[static_cast<size_t>(pick(rng))]);
          break;
        default:  // released: everything back to rest
          centres.clear();
          break;
      }
      std::vector<int32_t> now;
      for (int32_t v = 0; v < db.vertex_count(); ++v) {
        const Eigen::Vector3d& p = rest[static_cast<size_t>(v)];
        double push = 0.0;
        for (const Eigen::Vector3d& c : centres) {
          push = std::max(push, depth * (radius - (p - c).norm()) / radius);
        }
        positions[static_cast<size_t>(v)] = push > 0.0 ? Eigen::Vector3d(p * (1.0 - push)) : p;
        if (push > 0.0) now.push_back(v);
      }
      const std::vector<int32_t> moved = moved_between(displaced, now);
      displaced = now;
      if (moved.empty()) continue;
      db.set_positions(positions, moved, &scratch);
      edges.refit_moved_edges(scratch.moved, &edge_scratch);

      const std::string at = "step " + std::to_string(step);
      const std::vector<Eigen::Vector3d> normals = reference_vertex_normals(db);
      for (int32_t v = 0; v < db.vertex_count(); ++v) {
        ASSERT_EQ(db.position(v), positions[static_cast<size_t>(v)]) << at << " v " << v;
        ASSERT_EQ(db.vertex_normal(v), normals[static_cast<size_t>(v)]) << at << " v " << v;
      }
      for (int32_t f = 0; f < db.face_count(); ++f) {
        ASSERT_EQ(db.face_normal(f), face_normal_now(db, f)) << at << " f " << f;
      }
      std::string why;
      ASSERT_TRUE(boxes_match(
          db.tree(),
          [&](int32_t f, const auto& visit) {
            for (const int32_t v : db.face_vertices(f)) visit(db.position(v));
          },
          &why))
          << at << " face tree " << why;
      ASSERT_TRUE(boxes_match(
          edges.edge_tree(),
          [&](int32_t k, const auto& visit) {
            for (const int32_t v : db.edge_vertices(edges.tree_edges()[static_cast<size_t>(k)]))
              visit(db.position(v));
          },
          &why))
          << at << " edge tree " << why;
      std::set<int32_t> touched;
      const std::set<int32_t> moved_set(moved.begin(), moved.end());
      for (int32_t f = 0; f < db.face_count(); ++f) {
        const auto& t = db.face_vertices(f);
        if (moved_set.count(t[0]) + moved_set.count(t[1]) + moved_set.count(t[2]) == 0) continue;
        touched.insert(t.begin(), t.end());
      }
      ASSERT_EQ(std::vector<int32_t>(touched.begin(), touched.end()), scratch.dirty_vertices) << at;
    }
    // Both ways through the region were taken: changed, and held still.
    EXPECT_GT(scratch.regions_updated, 20);
    EXPECT_GT(scratch.regions_reused, 3);
  }
}

// The workspaces stay exact when used off their usual path: a mesh workspace moved to a copy of
// its database (its region is dropped and found afresh), and an edge workspace that missed one of
// the mesh's updates (it refits the whole edge tree once).
TEST(MeshDatabase, IncrementalWorkspacesStayExactOffTheirUsualPath) {
  const TriangleMesh m = make_uv_sphere(0.05, 30, 60);
  MeshDatabase db = MeshDatabase::build(m);
  SegmentDatabase edges = SegmentDatabase::build(db);
  MeshUpdateScratch scratch(db);
  SegmentUpdateScratch edge_scratch(edges);
  std::vector<Eigen::Vector3d> positions = m.positions;
  auto dent = [&](const Eigen::Vector3d& centre, std::vector<int32_t>* moved) {
    for (int32_t v = 0; v < db.vertex_count(); ++v) {
      const Eigen::Vector3d& p = m.positions[static_cast<size_t>(v)];
      const double d = (p - centre).norm();
      if (d >= 0.015 && positions[static_cast<size_t>(v)] == p) continue;
      positions[static_cast<size_t>(v)] = d < 0.015 ? Eigen::Vector3d(p * 0.9) : p;
      moved->push_back(v);
    }
  };
  auto edge_points = [&](const MeshDatabase& d, const SegmentDatabase& e) {
    return [&d, &e](int32_t k, const auto& visit) {
      for (const int32_t v : d.edge_vertices(e.tree_edges()[static_cast<size_t>(k)]))
        visit(d.position(v));
    };
  };
  std::string why;
  // Two updates of the mesh, one refit of the edges: the second dent's faces and the first's,
  // back at rest, are all refitted.
  std::vector<int32_t> first;
  dent(Eigen::Vector3d(0.05, 0.0, 0.0), &first);
  db.set_positions(positions, first, &scratch);
  edges.refit_moved_edges(scratch.moved, &edge_scratch);
  std::vector<int32_t> second;
  dent(Eigen::Vector3d(0.0, 0.05, 0.0), &second);
  db.set_positions(positions, second, &scratch);
  std::vector<int32_t> third;
  dent(Eigen::Vector3d(0.0, 0.0, 0.05), &third);
  db.set_positions(positions, third, &scratch);
  edges.refit_moved_edges(scratch.moved, &edge_scratch);
  EXPECT_TRUE(boxes_match(edges.edge_tree(), edge_points(db, edges), &why)) << why;
  // The workspace moved to a copy (same topology): the copy's normals and boxes are exact.
  MeshDatabase copy = db;
  SegmentDatabase copy_edges = edges.copy_for(copy);
  std::vector<int32_t> fourth;
  dent(Eigen::Vector3d(-0.05, 0.0, 0.0), &fourth);
  copy.set_positions(positions, fourth, &scratch);
  copy_edges.refit_moved_edges(scratch.moved, &edge_scratch);
  const std::vector<Eigen::Vector3d> normals = reference_vertex_normals(copy);
  for (int32_t v = 0; v < copy.vertex_count(); ++v) {
    ASSERT_EQ(copy.vertex_normal(v), normals[static_cast<size_t>(v)]) << "v " << v;
  }
  EXPECT_TRUE(boxes_match(
      copy.tree(),
      [&](int32_t f, const auto& visit) {
        for (const int32_t v : copy.face_vertices(f)) visit(copy.position(v));
      },
      &why))
      << why;
  EXPECT_TRUE(boxes_match(copy_edges.edge_tree(), edge_points(copy, copy_edges), &why)) << why;
}

// The moved set's difference from one list to the next, against std::set arithmetic, over
// random lists with repeats; the version moves on by one per change, by none for the same set
// again (the same list, or the same vertices in another order or repeated), by two when cleared.
TEST(VertexSetDelta, EnteredAndLeftAreTheSetDifferences) {
  VertexSetDelta delta(50);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int32_t> vertex(0, 49);
  std::uniform_int_distribution<int> length(0, 30);
  std::vector<int32_t> last;
  std::set<int32_t> before;
  for (int round = 0; round < 500; ++round) {
    std::vector<int32_t> list;
    if (round % 9 == 4) {
      list = last;  // the same list again
    } else if (round % 9 == 7) {
      list = last;  // the same vertices, reversed and one repeated
      std::reverse(list.begin(), list.end());
      if (!list.empty()) list.push_back(list.front());
    } else {
      for (int n = length(rng); n > 0; --n) list.push_back(vertex(rng));
    }
    const uint64_t version = delta.version();
    const bool changed = delta.update(list);
    const std::set<int32_t> now(list.begin(), list.end());
    EXPECT_EQ(changed, now != before) << round;
    EXPECT_EQ(delta.version(), version + (changed ? 1 : 0)) << round;
    std::vector<int32_t> want_current;
    std::set<int32_t> seen;
    for (const int32_t v : list) {
      if (seen.insert(v).second) want_current.push_back(v);
    }
    EXPECT_EQ(delta.current, want_current) << round;
    std::vector<int32_t> want_entered;
    std::vector<int32_t> want_left;
    if (changed) {
      for (const int32_t v : want_current) {
        if (before.count(v) == 0) want_entered.push_back(v);
      }
      for (const int32_t v : before) {
        if (now.count(v) == 0) want_left.push_back(v);
      }
    }
    EXPECT_EQ(delta.entered, want_entered) << round;
    std::vector<int32_t> left = delta.left;
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, want_left) << round;
    last = list;
    before = now;
  }
  const uint64_t version = delta.version();
  delta.clear();
  EXPECT_EQ(delta.version(), version + 2);
  EXPECT_TRUE(delta.current.empty());
  EXPECT_TRUE(delta.update(std::vector<int32_t>{1, 2}));
  EXPECT_EQ(delta.entered, (std::vector<int32_t>{1, 2}));
}

// The tree's nearest-face search (branch and bound) finds the same squared distance as trying
// every face, for points inside, near and far outside a sphere and a box.
TEST(BoundingVolumeTree, NearestFaceMatchesExhaustiveSearch) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const TriangleMesh& mesh :
       {make_uv_sphere(0.05, 24, 48), make_box(Eigen::Vector3d(0.1, 0.04, 0.06), 10)}) {
    const MeshDatabase db = MeshDatabase::build(mesh);
    for (int i = 0; i < 2000; ++i) {
      const double scale = i % 3 == 0 ? 0.02 : (i % 3 == 1 ? 0.06 : 1.0);
      const Eigen::Vector3d p(scale * u(rng), scale * u(rng), scale * u(rng));
      double best = 1e300;
      for (int32_t f = 0; f < db.face_count(); ++f) {
        const auto& v = db.face_vertices(f);
        TriangleFeature feature;
        best = std::min(best, (closest_on_triangle(p, db.position(v[0]), db.position(v[1]),
                                                   db.position(v[2]), &feature) -
                               p)
                                  .squaredNorm());
      }
      Eigen::Vector3d q;
      double d2 = 0.0;
      const int32_t f = db.nearest_face(p, &q, &d2);
      ASSERT_GE(f, 0);
      EXPECT_EQ(d2, best) << "point " << i;
      EXPECT_EQ((q - p).squaredNorm(), d2);
    }
  }
}

TEST(BoundingVolumeTree, NodeBoxesContainTheirFaces) {
  const MeshDatabase db = MeshDatabase::build(make_stand_in_liver());
  const auto& nodes = db.tree().nodes();
  for (const BvhNode& n : nodes) {
    if (n.count == 0) continue;
    for (int32_t f = n.first; f < n.first + n.count; ++f) {
      for (int32_t v : db.face_vertices(f)) {
        for (int a = 0; a < 3; ++a) {
          EXPECT_LE(n.lo[a], db.position(v)[a]);
          EXPECT_GE(n.hi[a], db.position(v)[a]);
        }
      }
    }
  }
  EXPECT_LE(db.tree().depth(), BoundingVolumeTree::kMaxDepth);
}

}  // namespace
}  // namespace lap::haptics

namespace lap::haptics {
namespace {

TEST(CornerAngle, AgreesWithStdAtan2) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> e(-12.0, 12.0);
  double worst = 0.0;
  for (int i = 0; i < 1000000; ++i) {
    const double scale = std::pow(10.0, e(rng));
    const double y = std::abs(u(rng)) * scale;
    const double x = u(rng) * scale;
    worst = std::max(worst, std::abs(corner_angle(y, x) - std::atan2(y, x)));
  }
  EXPECT_LT(worst, 2e-15);
  EXPECT_EQ(corner_angle(1.0, 0.0), std::atan2(1.0, 0.0));    // right angle, exactly
  EXPECT_EQ(corner_angle(1.0, 1.0), std::atan2(1.0, 1.0));    // 45 degrees, exactly
  EXPECT_EQ(corner_angle(0.0, -2.0), std::atan2(0.0, -2.0));  // straight angle
  EXPECT_EQ(corner_angle(0.0, 0.0), 0.0);
}

}  // namespace
}  // namespace lap::haptics
