#include "app/mesh_actor.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

namespace lap::app {

vtkSmartPointer<vtkActor> make_mesh_actor(const haptics::TriangleMesh& mesh, const double rgb[3]) {
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(mesh.vertex_count());
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector3d& p = mesh.positions[v];
    points->SetPoint(v, p.x(), p.y(), p.z());
  }
  vtkNew<vtkCellArray> cells;
  cells->AllocateExact(mesh.triangle_count(), 3 * mesh.triangle_count());
  for (const auto& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(cells);
  if (mesh.normals.size() == mesh.positions.size()) {
    vtkNew<vtkFloatArray> normals;
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(mesh.vertex_count());
    normals->SetName("Normals");
    for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
      const Eigen::Vector3d& n = mesh.normals[v];
      normals->SetTuple3(v, n.x(), n.y(), n.z());
    }
    poly->GetPointData()->SetNormals(normals);
  }
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* prop = actor->GetProperty();
  prop->SetColor(rgb[0], rgb[1], rgb[2]);
  prop->SetAmbient(0.25);
  prop->SetDiffuse(0.75);
  prop->SetSpecular(0.25);
  prop->SetSpecularPower(30.0);
  prop->SetInterpolationToPhong();
  return actor;
}

}  // namespace lap::app
