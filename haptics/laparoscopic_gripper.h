#pragma once
/// \file
/// The laparoscopic gripper as the haptic loop sees it (thesis §7.6.2, Figure 7-15): three line
/// segments — the shaft, and two jaws hinged at the shaft's tip and opened by the gripper angle
/// — each rendered by its own segment proxy (chapter 5) against the same objects. The three
/// contact wrenches are summed into one wrench at the tool (force, and torque about the hinge),
/// and the forces on the jaws that resist closing give the squeeze force for an actuated
/// gripper (§7.5).
///
/// The step allocates nothing, takes no lock and never throws.

#include <Eigen/Core>
#include <span>

#include "haptics/segment_proxy.h"

namespace lap::haptics {

struct GripperGeometry {
  double shaft_length_m = 0.30;  ///< hinge to the handle end of the rendered shaft
  double jaw_length_m = 0.02;    ///< hinge to jaw tip
};

/// Where the tool is this tick (world frame).
struct GripperPose {
  Eigen::Vector3d hinge_W = Eigen::Vector3d::Zero();  ///< the shaft's tip, where the jaws hinge
  Eigen::Vector3d shaft_dir_W = Eigen::Vector3d::UnitY();  ///< unit, from the hinge to the handle
  Eigen::Vector3d open_dir_W = Eigen::Vector3d::UnitX();   ///< unit, ⊥ shaft: jaw 0 opens along +
  double opening_rad = 0.0;                                ///< angle between the two jaws
};

struct GripperOutput {
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();   ///< on the tool [N]
  Eigen::Vector3d torque_W = Eigen::Vector3d::Zero();  ///< about the hinge [N m]
  double squeeze_n = 0.0;  ///< force resisting closure, mean over the two jaws [N]
  std::array<SegmentProxyOutput, 3> segments{};  ///< shaft, jaw 0, jaw 1
  bool fault = false;
};

class LaparoscopicGripper {
 public:
  explicit LaparoscopicGripper(const GripperGeometry& geometry = {},
                               const SegmentProxySettings& settings = {});

  /// The three segments (tip a, end b) for a pose: shaft (hinge -> handle), jaws (tip -> hinge).
  void segments(const GripperPose& pose, std::array<Eigen::Vector3d, 3>* a,
                std::array<Eigen::Vector3d, 3>* b) const;

  void reset(const GripperPose& pose);
  GripperOutput step(std::span<const HapticObject> objects, const GripperPose& pose,
                     double dt) noexcept;

  [[nodiscard]] const SegmentProxy& proxy(int i) const { return proxies_[i]; }
  [[nodiscard]] const GripperGeometry& geometry() const { return geometry_; }

 private:
  GripperGeometry geometry_;
  std::array<SegmentProxy, 3> proxies_;
};

}  // namespace lap::haptics
