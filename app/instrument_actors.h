#pragma once
/// \file
/// One instrument as the graphics loop draws it (thesis Figure 7-14): the insulated shaft at its
/// real radius, the steel clevis and two jaws of the tool's kind turning about the hinge with
/// the grip — rigid shapes (instrument_shapes.h) built once and moved each frame by their
/// matrices only.
///
/// Where it is drawn: at the proxies, not the device (thesis §7.6: the segments the haptic loop
/// renders stop on the tissue; the device's pose goes into it). The instrument stays rigid and
/// its shaft keeps passing through its port: its hinge is the device's moved by the largest
/// displacement any of its segment proxies' ends has from the device's segments (each end of a
/// segment in contact also lifted by that part's half-thickness along the contact's normal, since
/// the proxy is a line and the part has a body); each jaw turns to its own proxy's angle. So a
/// jaw or shaft pressed on an organ is drawn on its surface, never inside it.

#include <vtkActor.h>
#include <vtkMatrix4x4.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <array>

#include "app/instrument_shapes.h"
#include "haptics/laparoscopic_gripper.h"
#include "sim/runtime/session.h"

namespace lap::app {

/// What an instrument is drawn from (scenario and session model).
struct InstrumentSpec {
  InstrumentKind kind = InstrumentKind::kGrasper;
  double shaft_radius_m = 0.0025;
  haptics::GripperGeometry gripper;                  ///< shaft and jaw lengths
  Eigen::Vector3d port_W = Eigen::Vector3d::Zero();  ///< its trocar
};

/// The drawn pose (for tests and the camera assistant).
struct InstrumentPose {
  Eigen::Vector3d hinge_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d shaft_dir_W = Eigen::Vector3d::UnitY();  ///< unit, hinge towards the handle
  Eigen::Vector3d open_dir_W = Eigen::Vector3d::UnitX();   ///< unit, ⊥ shaft
  std::array<Eigen::Vector3d, 2> jaw_dir_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  std::array<Eigen::Vector3d, 2> jaw_tip_W{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
};

/// The drawn pose for a tool snapshot (the header's rule). Pure: tested on its own.
[[nodiscard]] InstrumentPose drawn_instrument_pose(const InstrumentSpec& spec,
                                                   const sim::ToolSnapshot& tool);

class InstrumentActors {
 public:
  /// Builds the shapes and adds the actors (hidden until the first update).
  void add(vtkRenderer* renderer, const InstrumentSpec& spec);
  /// Places them for the snapshot.
  void update(const sim::ToolSnapshot& tool);

  [[nodiscard]] const InstrumentPose& pose() const { return pose_; }
  [[nodiscard]] vtkActor* shaft() const { return shaft_; }
  [[nodiscard]] vtkActor* jaw(int j) const { return jaws_[static_cast<size_t>(j)]; }

 private:
  InstrumentSpec spec_;
  InstrumentPose pose_;
  vtkSmartPointer<vtkActor> shaft_;
  vtkSmartPointer<vtkActor> clevis_;
  std::array<vtkSmartPointer<vtkActor>, 2> jaws_;
  vtkSmartPointer<vtkMatrix4x4> body_matrix_;
  std::array<vtkSmartPointer<vtkMatrix4x4>, 2> jaw_matrices_;
};

}  // namespace lap::app
