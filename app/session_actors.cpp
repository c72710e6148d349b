#include "app/session_actors.h"

#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

namespace lap::app {
namespace {

constexpr int32_t kCatheterSides = 10;

}  // namespace

SessionDrawing session_drawing(const sim::Scene& scene, const sim::SessionModel& model) {
  SessionDrawing d;
  const sim::TissueModel& tissue = model.tissue();
  for (int32_t i = 0; i < tissue.organ_count(); ++i) {
    d.surfaces.push_back(&tissue.surface(i));
    OrganLook look;
    if (static_cast<size_t>(i) < scene.organs.size()) {
      const sim::Organ& organ = scene.organs[static_cast<size_t>(i)];
      look.colour = organ.color;
      look.albedo = organ.albedo;
    }
    d.looks.push_back(look);
  }
  for (size_t side = 0; side < 2; ++side) {
    InstrumentSpec& spec = d.instruments[side];
    const sim::ToolSpec* tool =
        scene.scenario.tool(side == 0 ? sim::ToolSpec::Side::kLeft : sim::ToolSpec::Side::kRight);
    if (tool != nullptr) {
      spec.kind = instrument_kind(tool->kind);
      spec.shaft_radius_m = tool->shaft_radius_m;
    }
    spec.gripper = model.tool(side).gripper;
    spec.port_W = model.tool(side).trocar.port_W;
  }
  // The tissue always has a catheter (a scenario without its section gets the default one); it
  // is drawn where the scenario has one or a task that needs it, not in a demonstration's scene
  // (where nothing touches it: the tools render the organs only).
  const bool catheter = scene.scenario.catheter.has_value() || scene.scenario.task.has_value();
  d.catheter_points = catheter ? tissue.catheter_model().particle_count() : 0;
  d.catheter_radius_m = tissue.catheter_model().radius_m();
  return d;
}

SessionDrawing replay_drawing(const sim::ReplayScene& scene) {
  SessionDrawing drawing;
  for (size_t o = 0; o < scene.organ_surfaces.size(); ++o) {
    drawing.surfaces.push_back(&scene.organ_surfaces[o]);
    OrganLook look;
    if (o < scene.organ_colours.size()) look.colour = scene.organ_colours[o];
    if (o < scene.organ_albedos.size()) look.albedo = scene.organ_albedos[o];
    drawing.looks.push_back(look);
  }
  for (size_t side = 0; side < 2; ++side) {
    InstrumentSpec& spec = drawing.instruments[side];
    if (!scene.tool_kinds[side].empty()) spec.kind = instrument_kind(scene.tool_kinds[side]);
    spec.shaft_radius_m = scene.tool_shaft_radius_m[side];
    spec.gripper = scene.tools[side];
    spec.port_W = scene.tool_port_W[side];
  }
  drawing.catheter_points = scene.catheter_points;
  drawing.catheter_radius_m = scene.catheter_radius_m;
  return drawing;
}

void SessionActors::add(vtkRenderer* renderer, const SessionDrawing& drawing) {
  organs_.add(renderer, drawing.surfaces, drawing.looks);
  for (size_t i = 0; i < 2; ++i) instruments_[i].add(renderer, drawing.instruments[i]);
  tube_.reset();
  catheter_poly_ = nullptr;
  catheter_actor_ = nullptr;
  if (drawing.catheter_points < 2) return;
  tube_ = std::make_unique<CatheterTube>(drawing.catheter_points, kCatheterSides);
  catheter_radius_m_ = drawing.catheter_radius_m;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(tube_->vertex_count());
  for (vtkIdType v = 0; v < tube_->vertex_count(); ++v) points->SetPoint(v, 0.0, 0.0, 0.0);
  catheter_normals_ = vtkSmartPointer<vtkFloatArray>::New();
  catheter_normals_->SetNumberOfComponents(3);
  catheter_normals_->SetNumberOfTuples(tube_->vertex_count());
  catheter_normals_->SetName("Normals");
  catheter_normals_->FillValue(0.0F);
  vtkNew<vtkCellArray> cells;
  const std::vector<int32_t>& tri = tube_->triangles();
  cells->AllocateExact(static_cast<vtkIdType>(tri.size() / 3), static_cast<vtkIdType>(tri.size()));
  for (size_t k = 0; k + 2 < tri.size(); k += 3) {
    const vtkIdType ids[3] = {tri[k], tri[k + 1], tri[k + 2]};
    cells->InsertNextCell(3, ids);
  }
  catheter_poly_ = vtkSmartPointer<vtkPolyData>::New();
  catheter_poly_->SetPoints(points);
  catheter_poly_->SetPolys(cells);
  catheter_poly_->GetPointData()->SetNormals(catheter_normals_);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(catheter_poly_);
  mapper->ScalarVisibilityOff();
  catheter_actor_ = vtkSmartPointer<vtkActor>::New();
  catheter_actor_->SetMapper(mapper);
  vtkProperty* p = catheter_actor_->GetProperty();
  // Polyurethane: milky white, glossy (a wet catheter).
  p->SetColor(0.9, 0.92, 0.95);
  p->SetAmbient(0.12);
  p->SetDiffuse(0.8);
  p->SetSpecular(0.7);
  p->SetSpecularPower(50.0);
  p->SetInterpolationToPhong();
  catheter_actor_->VisibilityOff();
  renderer->AddActor(catheter_actor_);
}

void SessionActors::update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model) {
  organs_.update(model);
  if (haptic.tick >= 0) {
    for (size_t i = 0; i < 2; ++i) instruments_[i].update(haptic.tools[i]);
  }
  if (tube_ != nullptr) {
    vtkPoints* points = catheter_poly_->GetPoints();
    const auto n = static_cast<size_t>(tube_->vertex_count()) * 3;
    const std::span<float> out(static_cast<float*>(points->GetVoidPointer(0)), n);
    const std::span<float> normals(catheter_normals_->GetPointer(0), n);
    if (tube_->write(model.catheter, catheter_radius_m_, out, normals)) {
      points->Modified();
      catheter_normals_->Modified();
      catheter_actor_->VisibilityOn();
    }
  }
}

}  // namespace lap::app
