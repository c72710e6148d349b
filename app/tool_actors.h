#pragma once
/// \file
/// What the graphics loop draws of the running session: each tool as its three segments (shaft
/// and jaws, Figure 7-15), the catheter as its centre line, as thick lines, and the organs'
/// surfaces as the modelling loop deforms them (§6.5: the deformed surface is the one drawn),
/// all updated in place from the newest snapshots.

#include <vtkActor.h>
#include <vtkFloatArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <array>
#include <memory>
#include <vector>

#include "haptics/laparoscopic_gripper.h"
#include "haptics/mesh_database.h"
#include "sim/runtime/deformed_surface.h"
#include "sim/runtime/session.h"

namespace lap::app {

class SessionActors {
 public:
  /// Adds the actors to `renderer`; `catheter_points` is the catheter's particle count.
  void add_to(vtkRenderer* renderer, const std::array<haptics::GripperGeometry, 2>& tools,
              int catheter_points);
  /// Adds one actor per organ surface (the session's, at rest: the duct is its shell), each
  /// deformed in place by update(): its points, and its normals (angle-weighted, §4.2) where
  /// the surface moved, so a dent is lit as the dent it is.
  void add_organs(vtkRenderer* renderer, const std::vector<const haptics::TriangleMesh*>& surfaces,
                  const std::vector<Eigen::Vector3d>& colours);
  /// Moves them to the snapshots' state.
  void update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model);

  /// The polygons drawn for organ o (points and normals as last updated).
  [[nodiscard]] vtkPolyData* organ_poly(size_t o) const { return organs_[o].poly; }

 private:
  struct OrganActor {
    vtkSmartPointer<vtkPolyData> poly;
    vtkSmartPointer<vtkFloatArray> normals;
    std::unique_ptr<haptics::MeshDatabase> db;  // the drawn surface's normals, updated locally
    std::unique_ptr<haptics::MeshUpdateScratch> scratch;
    sim::DeformedSurface surface;
  };
  std::array<haptics::LaparoscopicGripper, 2> grippers_;
  std::array<vtkSmartPointer<vtkPoints>, 2> tool_points_;
  std::array<vtkSmartPointer<vtkActor>, 2> tool_actors_;
  std::vector<OrganActor> organs_;
  int64_t organ_steps_ = 0;  ///< the model step the organ actors show
  vtkSmartPointer<vtkPoints> catheter_points_;
  vtkSmartPointer<vtkActor> catheter_actor_;
};

}  // namespace lap::app
