#pragma once
/// \file
/// What the graphics loop draws of the running session: each tool as its three segments (shaft
/// and jaws, Figure 7-15) and the catheter as its centre line, as thick lines updated in place
/// from the newest snapshots.

#include <vtkActor.h>
#include <vtkPoints.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <array>

#include "haptics/laparoscopic_gripper.h"
#include "sim/session.h"

namespace lap::app {

class SessionActors {
 public:
  /// Adds the actors to `renderer`; `catheter_points` is the catheter's particle count.
  void add_to(vtkRenderer* renderer, const std::array<haptics::GripperGeometry, 2>& tools,
              int catheter_points);
  /// Moves them to the snapshots' state.
  void update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model);

 private:
  std::array<haptics::LaparoscopicGripper, 2> grippers_;
  std::array<vtkSmartPointer<vtkPoints>, 2> tool_points_;
  std::array<vtkSmartPointer<vtkActor>, 2> tool_actors_;
  vtkSmartPointer<vtkPoints> catheter_points_;
  vtkSmartPointer<vtkActor> catheter_actor_;
};

}  // namespace lap::app
