#include "haptics/setup/mesh_validation.h"

#include <gtest/gtest.h>

#include <limits>

#include "haptics/setup/mesh_generators.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

using test::tetrahedron;

bool mentions(const MeshDiagnostics& d, const std::string& text) {
  for (const std::string& line : d.describe()) {
    if (line.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST(MeshValidation, ClosedTetrahedronIsClean) {
  const MeshDiagnostics d = validate_mesh(tetrahedron());
  EXPECT_TRUE(d.clean());
  EXPECT_TRUE(d.describe().empty());
  EXPECT_EQ(d.component_count, 1);
}

TEST(MeshValidation, NonFiniteCoordinates) {
  TriangleMesh m = tetrahedron();
  m.positions[3].z() = std::numeric_limits<double>::quiet_NaN();
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.non_finite_vertices, std::vector<int32_t>{3});
  EXPECT_FALSE(d.clean());
  EXPECT_TRUE(mentions(d, "1 non-finite vertex coordinates (vertices 3)"));
}

TEST(MeshValidation, OutOfRangeIndex) {
  TriangleMesh m = tetrahedron();
  m.triangles.push_back({0, 1, 7});
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.invalid_index_triangles, std::vector<int32_t>{4});
  EXPECT_FALSE(d.clean());
}

// Issue 25: validation read the positions of out-of-range triangles (the total area for the
// fragment test), a SIGSEGV when the index is far past the end. Indices this far out are never
// read now: only counted.
TEST(MeshValidation, FarOutOfRangeIndicesAreReportedWithoutBeingRead) {
  TriangleMesh m = tetrahedron();
  m.triangles.push_back({0, 1, 200'000'000});
  m.triangles.push_back({-100'000'000, 1, 2});
  // A second part, so that the fragment test (which needs the total area) runs.
  TriangleMesh far = tetrahedron(Eigen::Vector3d(5, 0, 0));
  m.append(far);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.invalid_index_triangles, (std::vector<int32_t>{4, 5}));
  EXPECT_TRUE(mentions(d, "2 triangles with an out-of-range vertex index (triangles 4, 5)"));
  EXPECT_EQ(d.vertex_count, 8);
  EXPECT_EQ(d.part_count, 2);
}

TEST(MeshValidation, DegenerateTrianglesRepeatedVertexAndZeroArea) {
  TriangleMesh m = tetrahedron();
  m.triangles.push_back({0, 0, 1});                   // repeated vertex
  m.positions.push_back(Eigen::Vector3d(0.5, 0, 0));  // collinear with 0 and 1
  m.triangles.push_back({0, 1, 4});
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.degenerate_triangles, (std::vector<int32_t>{4, 5}));
  EXPECT_FALSE(d.clean());
}

TEST(MeshValidation, SubMicrometreTrianglesAreNotDegenerate) {
  // Real scans have triangles with sub-micrometre edges; they are valid geometry in metres.
  const MeshDiagnostics d = validate_mesh(tetrahedron(Eigen::Vector3d(0.1, 0.1, 0.1), 1e-7));
  EXPECT_TRUE(d.degenerate_triangles.empty());
  EXPECT_TRUE(d.clean());
}

TEST(MeshValidation, DuplicateTrianglesInEitherWinding) {
  TriangleMesh m = tetrahedron();
  m.triangles.push_back({2, 1, 0});  // same vertex set as {0, 2, 1}
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.duplicate_triangles, std::vector<int32_t>{4});
  EXPECT_FALSE(d.clean());
}

TEST(MeshValidation, BoundaryEdgesOfAnOpenBox) {
  TriangleMesh box = make_box(Eigen::Vector3d(1, 1, 1), 1);
  box.triangles.erase(box.triangles.begin(), box.triangles.begin() + 2);  // remove one face
  const MeshDiagnostics d = validate_mesh(box);
  EXPECT_EQ(d.boundary_edges.size(), 4U);
  EXPECT_FALSE(d.closed());
  EXPECT_TRUE(d.non_manifold_vertices.empty());
  EXPECT_TRUE(d.orientation_conflict_edges.empty());
  EXPECT_TRUE(mentions(d, "4 boundary edges: the surface is not closed"));
}

TEST(MeshValidation, NonManifoldEdgeSharedByThreeTriangles) {
  TriangleMesh m = tetrahedron();
  m.positions.push_back(Eigen::Vector3d(0.3, -1, 0.3));
  m.triangles.push_back({0, 1, 4});  // a fin on edge 0-1
  const MeshDiagnostics d = validate_mesh(m);
  ASSERT_EQ(d.non_manifold_edges.size(), 1U);
  EXPECT_EQ(d.non_manifold_edges[0], (EdgeKey{0, 1}));
}

TEST(MeshValidation, NonManifoldVertexWhereTwoBodiesTouch) {
  TriangleMesh m = tetrahedron();
  TriangleMesh other = tetrahedron(Eigen::Vector3d(0, 0, 1));  // its corner 0 is our vertex 3
  m.append(other);
  for (Triangle& t : m.triangles) {
    for (int32_t& v : t) {
      if (v == 4) v = 3;  // share the vertex
    }
  }
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.non_manifold_vertices, std::vector<int32_t>{3});
  EXPECT_TRUE(d.boundary_edges.empty());
  EXPECT_TRUE(d.non_manifold_edges.empty());
}

TEST(MeshValidation, OneFlippedTriangleGivesThreeConflictingEdges) {
  TriangleMesh box = make_box(Eigen::Vector3d(1, 1, 1), 2);
  std::swap(box.triangles[5][1], box.triangles[5][2]);
  const MeshDiagnostics d = validate_mesh(box);
  EXPECT_EQ(d.orientation_conflict_edges.size(), 3U);
  EXPECT_EQ(d.flipped_triangles, std::vector<int32_t>{5});
  EXPECT_TRUE(d.boundary_edges.empty());
  EXPECT_FALSE(d.clean());
}

TEST(MeshValidation, InwardNormalsOfAConsistentlyInvertedMesh) {
  TriangleMesh s = make_uv_sphere(1.0, 6, 12);
  for (Triangle& t : s.triangles) std::swap(t[1], t[2]);
  const MeshDiagnostics d = validate_mesh(s);
  EXPECT_TRUE(d.orientation_conflict_edges.empty());
  EXPECT_EQ(d.inward_components, std::vector<int32_t>{0});
  EXPECT_TRUE(mentions(d, "closed components with inward-facing normals"));
}

TEST(MeshValidation, SliverFragmentsTouchingAtAVertexCountOnce) {
  TriangleMesh m = make_uv_sphere(0.05, 16, 32);
  const double before_area = m.surface_area();
  // Two nanometre-scale debris triangles sharing one vertex, far from the sphere, plus a lone
  // third one: two fragments.
  const int32_t b = m.vertex_count();
  const Eigen::Vector3d o(0.2, 0, 0);
  m.positions.insert(m.positions.end(),
                     {o, o + Eigen::Vector3d(1e-8, 0, 0), o + Eigen::Vector3d(0, 1e-8, 0),
                      o + Eigen::Vector3d(-1e-8, 0, 0), o + Eigen::Vector3d(0, -1e-8, 0)});
  m.triangles.push_back({b, b + 1, b + 2});
  m.triangles.push_back({b, b + 3, b + 4});
  const Eigen::Vector3d q(0.3, 0, 0);
  m.positions.insert(m.positions.end(),
                     {q, q + Eigen::Vector3d(1e-8, 0, 0), q + Eigen::Vector3d(0, 0, 1e-8)});
  m.triangles.push_back({b + 5, b + 6, b + 7});
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_EQ(d.sliver_fragments.size(), 2U);
  EXPECT_EQ(d.fragment_triangles, 3);
  EXPECT_EQ(d.component_count, 4);  // sphere + three edge-connected pieces
  // The debris' own open edges are not counted against the body (see MeshDiagnostics).
  EXPECT_TRUE(d.boundary_edges.empty());
  EXPECT_TRUE(d.non_manifold_vertices.empty());
  EXPECT_GT(before_area, 0.0);
  EXPECT_TRUE(mentions(d, "2 sliver fragments: small disconnected debris of 3 triangles"));
}

TEST(MeshValidation, TwoLargeBodiesAreNotFragments) {
  TriangleMesh m = make_uv_sphere(0.05, 8, 16);
  TriangleMesh other = make_uv_sphere(0.05, 8, 16);
  other.transform(Eigen::Affine3d(Eigen::Translation3d(0.2, 0, 0)));
  m.append(other);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_TRUE(d.sliver_fragments.empty());
  EXPECT_TRUE(d.clean());
  EXPECT_EQ(d.component_count, 2);
}

}  // namespace
}  // namespace lap::haptics
