#include "app/tool_actors.h"

#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

#include "app/mesh_actor.h"

namespace lap::app {
namespace {

vtkSmartPointer<vtkActor> line_actor(vtkPoints* points, vtkCellArray* lines, double width,
                                     const double rgb[3]) {
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(lines);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* p = actor->GetProperty();
  p->SetColor(rgb[0], rgb[1], rgb[2]);
  p->SetLineWidth(static_cast<float>(width));
  p->SetRenderLinesAsTubes(true);
  p->SetSpecular(0.5);
  return actor;
}

}  // namespace

void SessionActors::add_to(vtkRenderer* renderer,
                           const std::array<haptics::GripperGeometry, 2>& tools,
                           int catheter_points) {
  const double steel[3] = {0.75, 0.77, 0.80};
  for (size_t i = 0; i < 2; ++i) {
    grippers_[i] = haptics::LaparoscopicGripper(tools[i]);
    tool_points_[i] = vtkSmartPointer<vtkPoints>::New();
    tool_points_[i]->SetNumberOfPoints(6);
    for (int k = 0; k < 6; ++k) tool_points_[i]->SetPoint(k, 0.0, 0.0, 0.0);
    vtkNew<vtkCellArray> lines;
    for (vtkIdType k = 0; k < 3; ++k) {
      const vtkIdType ids[2] = {2 * k, 2 * k + 1};
      lines->InsertNextCell(2, ids);
    }
    tool_actors_[i] = line_actor(tool_points_[i], lines, 8.0, steel);
    renderer->AddActor(tool_actors_[i]);
  }
  catheter_points_ = vtkSmartPointer<vtkPoints>::New();
  catheter_points_->SetNumberOfPoints(catheter_points);
  for (int k = 0; k < catheter_points; ++k) catheter_points_->SetPoint(k, 0.0, 0.0, 0.0);
  vtkNew<vtkCellArray> line;
  line->InsertNextCell(catheter_points);
  for (vtkIdType k = 0; k < catheter_points; ++k) line->InsertCellPoint(k);
  const double white[3] = {0.92, 0.92, 0.88};
  catheter_actor_ = line_actor(catheter_points_, line, 5.0, white);
  renderer->AddActor(catheter_actor_);
}

void SessionActors::add_organs(vtkRenderer* renderer,
                               const std::vector<const haptics::TriangleMesh*>& surfaces,
                               const std::vector<Eigen::Vector3d>& colours) {
  organs_.clear();
  organ_steps_ = 0;
  for (size_t i = 0; i < surfaces.size() && i < colours.size(); ++i) {
    const double rgb[3] = {colours[i].x(), colours[i].y(), colours[i].z()};
    vtkSmartPointer<vtkActor> actor = make_mesh_actor(*surfaces[i], rgb);
    renderer->AddActor(actor);
    OrganActor a{
        vtkPolyData::SafeDownCast(actor->GetMapper()->GetInput()),
        vtkSmartPointer<vtkFloatArray>::New(),
        std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(*surfaces[i])),
        nullptr, sim::DeformedSurface(surfaces[i]->positions)};
    a.scratch = std::make_unique<haptics::MeshUpdateScratch>(*a.db);
    // The database's vertex normals from the start, so a dent's normals match their
    // surroundings' (a mesh file's own normals may be computed otherwise).
    a.normals->SetNumberOfComponents(3);
    a.normals->SetNumberOfTuples(a.db->vertex_count());
    a.normals->SetName("Normals");
    for (int32_t v = 0; v < a.db->vertex_count(); ++v) {
      const Eigen::Vector3d& n = a.db->vertex_normal(v);
      a.normals->SetTuple3(v, n.x(), n.y(), n.z());
    }
    a.poly->GetPointData()->SetNormals(a.normals);
    organs_.push_back(std::move(a));
  }
}

void SessionActors::update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model) {
  if (model.steps != organ_steps_) {
    organ_steps_ = model.steps;
    for (size_t o = 0; o < organs_.size() && o < model.organs.size(); ++o) {
      OrganActor& a = organs_[o];
      if (!a.surface.apply_to(model.organs[o], {.db = a.db.get(), .scratch = a.scratch.get()}))
        continue;
      // Every vertex whose normal the update recomputed (the moved ones among them).
      vtkPoints* points = a.poly->GetPoints();
      for (const int32_t v : a.scratch->dirty_vertices) {
        const Eigen::Vector3d& p = a.db->position(v);
        const Eigen::Vector3d& n = a.db->vertex_normal(v);
        points->SetPoint(v, p.x(), p.y(), p.z());
        a.normals->SetTuple3(v, n.x(), n.y(), n.z());
      }
      points->Modified();
      a.normals->Modified();
    }
  }
  if (haptic.tick >= 0) {
    for (size_t i = 0; i < 2; ++i) {
      std::array<Eigen::Vector3d, 3> a;
      std::array<Eigen::Vector3d, 3> b;
      grippers_[i].segments(haptic.tools[i].pose, &a, &b);
      for (int k = 0; k < 3; ++k) {
        tool_points_[i]->SetPoint(2 * k, a[k].x(), a[k].y(), a[k].z());
        tool_points_[i]->SetPoint(2 * k + 1, b[k].x(), b[k].y(), b[k].z());
      }
      tool_points_[i]->Modified();
    }
  }
  const auto n = static_cast<vtkIdType>(model.catheter.size());
  if (catheter_points_ != nullptr && n == catheter_points_->GetNumberOfPoints()) {
    for (vtkIdType k = 0; k < n; ++k) {
      const Eigen::Vector3d& p = model.catheter[static_cast<size_t>(k)];
      catheter_points_->SetPoint(k, p.x(), p.y(), p.z());
    }
    catheter_points_->Modified();
  }
}

}  // namespace lap::app
