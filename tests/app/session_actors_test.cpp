// What the graphics loop draws of a deforming organ (§6.5: the deformed surface is the one drawn):
// the actor's points are the published positions, its normals those of the dented surface (a
// database built afresh over it is the reference), and a vertex the next snapshot no longer
// displaces is back at rest. VTK objects only: no window, no display needed.

#include "app/session_actors.h"

#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/setup/mesh_generators.h"

namespace lap::app {
namespace {

// A dent of depth `depth` [m] toward the centre, linear over 15 mm around `centre`.
sim::SurfaceDeformation dent(const haptics::TriangleMesh& m, const Eigen::Vector3d& centre,
                             double depth) {
  sim::SurfaceDeformation d(m.positions.size());
  for (size_t v = 0; v < m.positions.size(); ++v) {
    const double dist = (m.positions[v] - centre).norm();
    if (dist >= 0.015) continue;
    d.vertex[static_cast<size_t>(d.count)] = static_cast<int32_t>(v);
    d.position[static_cast<size_t>(d.count++)] =
        m.positions[v] * (1.0 - depth / m.positions[v].norm() * (0.015 - dist) / 0.015);
  }
  return d;
}

// The mesh with a deformation's vertices moved: the reference the drawing is checked against.
haptics::TriangleMesh deformed(const haptics::TriangleMesh& m, const sim::SurfaceDeformation& d) {
  haptics::TriangleMesh out = m;
  for (int32_t k = 0; k < d.count; ++k) {
    out.positions[static_cast<size_t>(d.vertex[static_cast<size_t>(k)])] =
        d.position[static_cast<size_t>(k)];
  }
  return out;
}

// Largest distance between the drawn points / normals and the expected ones.
struct Drawn {
  double points = 0.0;
  double normals = 0.0;
};
Drawn compare(vtkPolyData* poly, const std::vector<Eigen::Vector3d>& positions,
              const haptics::MeshDatabase& reference) {
  Drawn worst;
  vtkDataArray* normals = poly->GetPointData()->GetNormals();
  for (vtkIdType v = 0; v < poly->GetNumberOfPoints(); ++v) {
    double p[3];
    double n[3];
    poly->GetPoint(v, p);
    normals->GetTuple(v, n);
    const auto i = static_cast<size_t>(v);
    worst.points =
        std::max(worst.points, (Eigen::Vector3d(p[0], p[1], p[2]) - positions[i]).norm());
    worst.normals = std::max(worst.normals, (Eigen::Vector3d(n[0], n[1], n[2]) -
                                             reference.vertex_normal(static_cast<int32_t>(v)))
                                                .norm());
  }
  return worst;
}

TEST(SessionActors, AnOrganIsDrawnDentedAndLitAsItsDentedShape) {
  const haptics::TriangleMesh sphere = haptics::make_uv_sphere(0.05, 40, 80);
  vtkNew<vtkRenderer> renderer;
  SessionActors actors;
  SessionDrawing drawing;
  drawing.surfaces = {&sphere};
  drawing.looks = {{Eigen::Vector3d(0.8, 0.3, 0.3), nullptr}};
  actors.add(renderer, drawing);
  vtkPolyData* poly = actors.organ_poly(0);
  ASSERT_EQ(poly->GetNumberOfPoints(), sphere.vertex_count());

  sim::HapticSnapshot haptic;  // tick -1: no tools yet
  sim::ModelSnapshot model;
  model.organs.push_back(dent(sphere, Eigen::Vector3d(0.05, 0.0, 0.0), 0.004));
  model.steps = 1;
  ASSERT_GT(model.organs[0].count, 10);
  actors.update(haptic, model);

  // The reference: the dented mesh built afresh.
  const haptics::TriangleMesh dented = deformed(sphere, model.organs[0]);
  const haptics::MeshDatabase fresh = haptics::MeshDatabase::build(dented);
  const haptics::MeshDatabase rest = haptics::MeshDatabase::build(sphere);
  const Drawn first = compare(poly, dented.positions, fresh);
  const Drawn stale = compare(poly, dented.positions, rest);  // normals left at rest would be this
  std::printf("dent drawn: points within %.2e m, normals within %.2e (rest normals off by %.3f)\n",
              first.points, first.normals, stale.normals);
  EXPECT_LT(first.points, 1e-8);   // vtkPoints hold floats: ~1e-9 m at 5 cm
  EXPECT_LT(first.normals, 1e-6);  // float normals
  EXPECT_GT(stale.normals, 0.1);   // the dent does turn them: the comparison can tell

  // The next snapshot dents elsewhere: the first dent springs back, points and normals.
  model.organs[0] = dent(sphere, Eigen::Vector3d(-0.05, 0.0, 0.0), 0.004);
  model.steps = 2;
  actors.update(haptic, model);
  const haptics::TriangleMesh second = deformed(sphere, model.organs[0]);
  const Drawn after = compare(poly, second.positions, haptics::MeshDatabase::build(second));
  EXPECT_LT(after.points, 1e-8);
  EXPECT_LT(after.normals, 1e-6);
}

}  // namespace
}  // namespace lap::app
