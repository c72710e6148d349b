#include "app/instrument_actors.h"

#include <vtkProperty.h>

#include <algorithm>
#include <cmath>

#include "app/mesh_actor.h"

namespace lap::app {
namespace {

// How far the part drawn round each segment reaches from its line: the shaft's radius, a jaw's
// back (the shapes' depth, instrument_shapes.cpp, at most 0.8 of the radius).
constexpr double kJawThicknessShare = 0.8;

void set_matrix(vtkMatrix4x4* m, const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                const Eigen::Vector3d& z, const Eigen::Vector3d& origin) {
  for (int r = 0; r < 3; ++r) {
    m->SetElement(r, 0, x[r]);
    m->SetElement(r, 1, y[r]);
    m->SetElement(r, 2, z[r]);
    m->SetElement(r, 3, origin[r]);
  }
  m->SetElement(3, 0, 0.0);
  m->SetElement(3, 1, 0.0);
  m->SetElement(3, 2, 0.0);
  m->SetElement(3, 3, 1.0);
  m->Modified();
}

void steel(vtkActor* a) {
  vtkProperty* p = a->GetProperty();
  p->SetColor(0.62, 0.64, 0.67);
  p->SetAmbient(0.1);
  p->SetDiffuse(0.55);
  p->SetSpecular(0.9);
  p->SetSpecularPower(60.0);
  p->SetInterpolationToPhong();
}

}  // namespace

InstrumentPose drawn_instrument_pose(const InstrumentSpec& spec, const sim::ToolSnapshot& tool) {
  const haptics::GripperPose& device = tool.pose;
  // The device's three segments, as LaparoscopicGripper::segments places them: the shaft from
  // the hinge (a) up to the handle (b), each jaw from its tip (a) to the hinge (b).
  std::array<Eigen::Vector3d, 3> a;
  std::array<Eigen::Vector3d, 3> b;
  a[0] = device.hinge_W;
  b[0] = device.hinge_W + spec.gripper.shaft_length_m * device.shaft_dir_W;
  for (size_t j = 0; j < 2; ++j) {
    const double side = j == 0 ? 1.0 : -1.0;
    const double half = 0.5 * device.opening_rad;
    a[j + 1] =
        device.hinge_W + spec.gripper.jaw_length_m * (-std::cos(half) * device.shaft_dir_W +
                                                      side * std::sin(half) * device.open_dir_W);
    b[j + 1] = device.hinge_W;
  }
  // The largest push out of the tissue among the segments' ends (the shaft's handle end, outside
  // the abdomen, excluded), each end of a touching segment lifted by its part's half-thickness.
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  for (size_t s = 0; s < 3; ++s) {
    const double thickness =
        s == 0 ? spec.shaft_radius_m : kJawThicknessShare * spec.shaft_radius_m;
    const Eigen::Vector3d lift = thickness * tool.proxy_normal_W[s];
    const bool placed = !tool.proxy_a_W[s].isZero() || !tool.proxy_b_W[s].isZero();
    if (!placed) continue;
    std::array<Eigen::Vector3d, 2> ends = {tool.proxy_a_W[s] + lift - a[s],
                                           tool.proxy_b_W[s] + lift - b[s]};
    for (size_t e = 0; e < (s == 0 ? 1U : 2U); ++e) {
      if (ends[e].allFinite() && ends[e].norm() > shift.norm()) shift = ends[e];
    }
  }
  InstrumentPose p;
  p.hinge_W = device.hinge_W + shift;
  if (spec.kind == InstrumentKind::kProbe) {
    // A probe (point or ray) is drawn with its tip where its proxy holds it (the IHIP, or the
    // ray's ideal tip), its rod through the port; it has no jaws.
    const bool held = !tool.proxy_tip_W.isZero() && tool.proxy_tip_W.allFinite();
    // The ball is lifted by its radius along the contact's normal, where one is known, so that
    // it rests on the surface instead of half inside it.
    p.hinge_W =
        held ? Eigen::Vector3d(tool.proxy_tip_W + spec.shaft_radius_m * tool.proxy_normal_W[0])
             : device.hinge_W;
  }
  const Eigen::Vector3d to_port = spec.port_W - p.hinge_W;
  p.shaft_dir_W = to_port.norm() > 1e-3 ? Eigen::Vector3d(to_port.normalized())
                                        : device.shaft_dir_W.normalized();
  Eigen::Vector3d open = device.open_dir_W - device.open_dir_W.dot(p.shaft_dir_W) * p.shaft_dir_W;
  p.open_dir_W =
      open.norm() > 1e-9 ? Eigen::Vector3d(open.normalized()) : p.shaft_dir_W.unitOrthogonal();
  if (spec.kind == InstrumentKind::kProbe) {
    for (size_t j = 0; j < 2; ++j) {
      p.jaw_dir_W[j] = -p.shaft_dir_W;
      p.jaw_tip_W[j] = p.hinge_W;
    }
    return p;
  }
  for (size_t j = 0; j < 2; ++j) {
    const double side = j == 0 ? 1.0 : -1.0;
    // The jaw's angle from the shaft as its proxy has it (a jaw pressed on tissue is turned by
    // it), never past the shaft's line.
    double half = 0.5 * device.opening_rad;
    const Eigen::Vector3d along = tool.proxy_a_W[j + 1] - tool.proxy_b_W[j + 1];
    if (along.norm() > 1e-6 && along.allFinite()) {
      const Eigen::Vector3d d = along.normalized();
      half = std::atan2(d.dot(side * device.open_dir_W), d.dot(-device.shaft_dir_W));
    }
    half = std::clamp(half, 0.0, 0.5 * M_PI);
    p.jaw_dir_W[j] = std::cos(half) * -p.shaft_dir_W + side * std::sin(half) * p.open_dir_W;
    p.jaw_tip_W[j] = p.hinge_W + spec.gripper.jaw_length_m * p.jaw_dir_W[j];
  }
  return p;
}

void InstrumentActors::add(vtkRenderer* renderer, const InstrumentSpec& spec) {
  spec_ = spec;
  const double white[3] = {1.0, 1.0, 1.0};
  const bool probe = spec.kind == InstrumentKind::kProbe;
  shaft_ = make_mesh_actor(
      make_shaft(spec.shaft_radius_m, spec.gripper.shaft_length_m, probe ? 0.0 : kClevisLengthM),
      white);
  if (probe) {
    steel(shaft_);  // a steel stylus
  } else {
    vtkProperty* p = shaft_->GetProperty();
    p->SetColor(0.035, 0.035, 0.04);  // black insulation
    p->SetAmbient(0.1);
    p->SetDiffuse(0.6);
    p->SetSpecular(0.45);
    p->SetSpecularPower(25.0);
  }
  // A probe ends in a steel ball of its rod's radius at its tip; an instrument in its clevis.
  clevis_ = make_mesh_actor(
      probe ? make_probe_tip(spec.shaft_radius_m) : make_clevis(spec.shaft_radius_m), white);
  steel(clevis_);
  body_matrix_ = vtkSmartPointer<vtkMatrix4x4>::New();
  shaft_->SetUserMatrix(body_matrix_);
  clevis_->SetUserMatrix(body_matrix_);
  for (size_t j = 0; j < 2; ++j) {
    jaws_[j] = make_mesh_actor(
        make_jaw(spec.kind, spec.gripper.jaw_length_m, spec.shaft_radius_m, j == 0 ? 1 : -1),
        white);
    steel(jaws_[j]);
    jaw_matrices_[j] = vtkSmartPointer<vtkMatrix4x4>::New();
    jaws_[j]->SetUserMatrix(jaw_matrices_[j]);
  }
  for (vtkActor* a : {shaft_.Get(), clevis_.Get(), jaws_[0].Get(), jaws_[1].Get()}) {
    a->VisibilityOff();
    renderer->AddActor(a);
  }
}

void InstrumentActors::update(const sim::ToolSnapshot& tool) {
  if (shaft_ == nullptr) return;
  pose_ = drawn_instrument_pose(spec_, tool);
  const InstrumentPose& p = pose_;
  set_matrix(body_matrix_, p.open_dir_W, p.shaft_dir_W, p.open_dir_W.cross(p.shaft_dir_W),
             p.hinge_W);
  for (size_t j = 0; j < 2; ++j) {
    const double side = j == 0 ? 1.0 : -1.0;
    const Eigen::Vector3d y = -p.jaw_dir_W[j];
    Eigen::Vector3d x = side * (p.open_dir_W - p.open_dir_W.dot(y) * y);
    x = x.norm() > 1e-9 ? Eigen::Vector3d(x.normalized()) : y.unitOrthogonal();
    set_matrix(jaw_matrices_[j], x, y, x.cross(y), p.hinge_W);
  }
  shaft_->VisibilityOn();
  clevis_->VisibilityOn();
  for (vtkActor* jaw : {jaws_[0].Get(), jaws_[1].Get()}) {
    jaw->SetVisibility(spec_.kind == InstrumentKind::kProbe ? 0 : 1);
  }
}

}  // namespace lap::app
