// The real organ scans in ../shared/meshes (read from there, never copied into the project).
// Expected counts come from ../shared/meshes/SOURCES.md.

#include <gtest/gtest.h>

#include "haptics/setup/mesh_repair.h"
#include "haptics/setup/mesh_validation.h"
#include "sim/setup/mesh_loader.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

using haptics::MeshDiagnostics;
using haptics::TriangleMesh;

struct CleanCase {
  const char* file;
  int triangles;
};

// Names the case in test listings instead of dumping its bytes.
void PrintTo(const CleanCase& c, std::ostream* os) { *os << c.file; }

class RealCleanMesh : public ::testing::TestWithParam<CleanCase> {};

TEST_P(RealCleanMesh, LoadsClosedOrientedAndOutwardInMetres) {
  LAP_REQUIRE_SHARED_MESHES();
  const CleanCase c = GetParam();
  const TriangleMesh m = load_mesh(test::shared_meshes_dir() / c.file, {0.001, 0.0}).value();
  EXPECT_EQ(m.triangle_count(), c.triangles);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_TRUE(d.clean()) << c.file;
  EXPECT_EQ(d.component_count, 1);
  // Closed genus-0 surfaces: V - E + F = 2 with E = 3F/2.
  EXPECT_EQ(m.vertex_count() - m.triangle_count() * 3 / 2 + m.triangle_count(), 2) << c.file;
  EXPECT_GT(m.signed_volume(), 0.0);
  // Organ-sized in metres: between 1 cm and 60 cm across.
  const double size = m.bounds().sizes().maxCoeff();
  EXPECT_GT(size, 0.01);
  EXPECT_LT(size, 0.6);
}

INSTANTIATE_TEST_SUITE_P(SharedMeshes, RealCleanMesh,
                         ::testing::Values(CleanCase{"liver_openhelp.stl", 30726},
                                           CleanCase{"stomach_openhelp.stl", 9724},
                                           CleanCase{"duodenum_openhelp.stl", 6946},
                                           CleanCase{"abdominal_wall_openhelp.stl", 31934},
                                           CleanCase{"gallbladder_sofaenv_glt.stl", 14700}),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           return name.substr(0, name.find('.'));
                         });

TEST(RealDefectiveMesh, LiverSofaEnvIsDiagnosedExactly) {
  LAP_REQUIRE_SHARED_MESHES();
  const TriangleMesh m =
      load_mesh(test::shared_meshes_dir() / "liver_sofaenv_glt.stl", {0.001, 0.0}).value();
  EXPECT_EQ(m.triangle_count(), 28716);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_FALSE(d.clean());
  EXPECT_EQ(d.boundary_edges.size(), 14U);
  EXPECT_EQ(d.non_manifold_vertices.size(), 1U);
  EXPECT_EQ(d.sliver_fragments.size(), 25U);
  EXPECT_EQ(d.orientation_conflict_edges.size(), 28U);
  EXPECT_TRUE(d.non_manifold_edges.empty());
  EXPECT_TRUE(d.degenerate_triangles.empty());
  EXPECT_TRUE(d.duplicate_triangles.empty());
  EXPECT_TRUE(d.non_finite_vertices.empty());
  const std::vector<std::string> lines = d.describe();
  auto has = [&lines](const std::string& prefix) {
    return std::any_of(lines.begin(), lines.end(),
                       [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
  };
  EXPECT_TRUE(has("14 boundary edges: the surface is not closed"));
  EXPECT_TRUE(has("1 non-manifold vertices"));
  EXPECT_TRUE(has("25 sliver fragments"));
  EXPECT_TRUE(has("28 edges with inconsistent orientation"));
}

TEST(RealDefectiveMesh, LiverSofaEnvRepairsIntoAClosedOrientedMesh) {
  LAP_REQUIRE_SHARED_MESHES();
  TriangleMesh m =
      load_mesh(test::shared_meshes_dir() / "liver_sofaenv_glt.stl", {0.001, 0.0}).value();
  const double area_before = m.surface_area();
  const haptics::MeshRepairReport r = repair_mesh(m);
  EXPECT_EQ(r.removed_fragments, 25);
  EXPECT_EQ(r.split_vertices, 1);
  EXPECT_GE(r.closed_holes, 1);
  EXPECT_EQ(r.holes_left_open, 0);
  const MeshDiagnostics d = validate_mesh(m);
  EXPECT_TRUE(d.clean()) << (d.describe().empty() ? "" : d.describe().front());
  EXPECT_EQ(d.component_count, 1);
  EXPECT_GT(m.signed_volume(), 0.0);
  // The debris and the patch are tiny: the organ's area changes by well under 0.1%.
  EXPECT_NEAR(m.surface_area(), area_before, 1e-3 * area_before);
  // The repaired body is a genus-0 closed surface.
  EXPECT_EQ(m.vertex_count() - m.triangle_count() * 3 / 2 + m.triangle_count(), 2);
}

}  // namespace
}  // namespace lap::sim
