#include "app/tool_actors.h"

#include <vtkCellArray.h>
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
  organ_points_.clear();
  organ_surfaces_.clear();
  organ_steps_ = 0;
  for (size_t i = 0; i < surfaces.size() && i < colours.size(); ++i) {
    const double rgb[3] = {colours[i].x(), colours[i].y(), colours[i].z()};
    vtkSmartPointer<vtkActor> actor = make_mesh_actor(*surfaces[i], rgb);
    renderer->AddActor(actor);
    organ_points_.emplace_back(
        vtkPolyData::SafeDownCast(actor->GetMapper()->GetInput())->GetPoints());
    organ_surfaces_.emplace_back(surfaces[i]->positions);
  }
}

void SessionActors::update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model) {
  if (model.steps != organ_steps_) {
    organ_steps_ = model.steps;
    for (size_t o = 0; o < organ_points_.size() && o < model.organs.size(); ++o) {
      const std::span<const int32_t> changed = organ_surfaces_[o].apply(model.organs[o]);
      for (const int32_t v : changed) {
        const Eigen::Vector3d& p = organ_surfaces_[o].positions()[static_cast<size_t>(v)];
        organ_points_[o]->SetPoint(v, p.x(), p.y(), p.z());
      }
      if (!changed.empty()) organ_points_[o]->Modified();
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
  if (n == catheter_points_->GetNumberOfPoints()) {
    for (vtkIdType k = 0; k < n; ++k) {
      const Eigen::Vector3d& p = model.catheter[static_cast<size_t>(k)];
      catheter_points_->SetPoint(k, p.x(), p.y(), p.z());
    }
    catheter_points_->Modified();
  }
}

}  // namespace lap::app
