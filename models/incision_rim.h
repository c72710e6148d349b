#pragma once
/// \file
/// The incision's rim holding the catheter that passes through it (thesis §7.4, Figure 7-18):
/// where the catheter's centre line crosses the duct's wall inside the ductotomy, the rim — the
/// cut wall, stretched round the catheter — keeps that crossing in the hole. Without it the
/// catheter's contacts, which act on its particles a few millimetres apart, let the segment
/// between a particle in the lumen and one outside cross the wall anywhere: pushed at a slant,
/// the catheter's body slides along the wall away from the hole while only its tip is inside.
///
/// The hold is a centre-line anchor (catheter_model.h) at the crossing, pulled towards the
/// incision's centre across the catheter only: its anchor friction has no limit along the
/// catheter, so the catheter slides through the rim freely (the lumen's own friction acts on
/// its particles inside). Inside the catheter's implicit step, as the grasps' anchors.
///
/// The duct frame D: z along the axis from the duct's start (0 to length_m), the wall's
/// mid-surface at radius mid_radius_m.
///
/// Real time: no allocation.

#include <Eigen/Geometry>
#include <span>

#include "models/catheter_model.h"

namespace lap::models {

struct IncisionRim {
  Eigen::Isometry3d pose_DW = Eigen::Isometry3d::Identity();  ///< world to duct frame
  double length_m = 0.0;                                      ///< the duct's, along z
  double mid_radius_m = 0.0;                                  ///< the wall's mid-surface
  double z_m = 0.0;        ///< the incision's centre along the axis
  double angle_rad = 0.0;  ///< and about it
  /// Its half axes along the axis and around it (arc length on the mid-surface) [m]: where a
  /// crossing counts as through the incision.
  double half_length_m = 0.0;
  double half_width_m = 0.0;
  /// The rim's pull on the catheter across it, towards the incision's centre (estimate: a few
  /// hundredths of a newton per millimetre off centre, soft next to the wall's 200–340 N/m, so
  /// the hole centres the catheter without stiffening the duct's feel).
  double stiffness_n_per_m = 50.0;
  double damping_n_s_per_m = 0.05;  ///< estimate
};

/// Where a catheter segment crosses the wall: its segment and fraction, and the crossing in the
/// duct frame.
struct RimCrossing {
  int32_t segment = -1;  ///< -1: no segment crosses the wall inside the incision
  double t = 0.0;
  Eigen::Vector3d point_D = Eigen::Vector3d::Zero();
};

/// The segment that crosses the wall's mid-surface inside the incision (the one nearest its
/// centre, if several do).
[[nodiscard]] RimCrossing find_rim_crossing(const IncisionRim& rim,
                                            std::span<const Eigen::Vector3d> positions) noexcept;

/// Anchors the catheter at its crossing through the incision, if it crosses there; true if it
/// did (false also when the catheter's anchors or frictions are all in use).
bool hold_at_incision(const IncisionRim& rim, const CatheterModel& model,
                      CatheterState* state) noexcept;

}  // namespace lap::models
