#pragma once
/// \file
/// The laparoscope (thesis §7.8: "a camera … adjusted using keyboard … zoom in for a bigger
/// image"): a rigid scope through its own port on the abdominal wall, the objective and the
/// light at its tip. Like an instrument through its trocar (trocar_tool.h) the scope pivots
/// about the port, slides in and out through it and turns about its own axis; its optic looks
/// along the axis (0°) or at an angle to it (30°), so turning an angled scope turns the view
/// about the axis. The camera head on the eyepiece keeps the picture's horizon level (the
/// assistant holds it upright while turning the scope's light post) unless turned itself.
///
/// Frames (world, y up): `axis` is the unit direction from the port to the tip; the scope's
/// reference "up" r0 is the horizon's up (CameraSpec::view_up) made perpendicular to the axis,
/// and s0 = axis × r0. At roll φ the optic is tilted by the optic angle θ towards
/// o(φ) = cos φ r0 + sin φ s0, so the line of sight is
///     v = cos θ axis + sin θ o(φ),
/// the eye is port + insertion · axis, and the picture's up is the horizon's up made
/// perpendicular to v, then turned about v by the camera head's angle.
///
/// Pure geometry (Eigen only): the app turns a LaparoscopeView into its camera and light. It is
/// the graphics loop's and never feeds the task engine, whose view cone stays the scenario's
/// fixed camera so that a session scores the same however the scope was moved (task_model.h).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/result.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

/// Where the scope is: the state the keys and the camera assistant move.
struct LaparoscopeState {
  Eigen::Vector3d axis_W = -Eigen::Vector3d::UnitZ();  ///< unit, from the port to the tip
  double insertion_m = 0.05;                           ///< port to tip along the axis [m]
  double roll_rad = 0.0;         ///< the optic's turn about the axis (0: it looks towards r0)
  double horizon_rad = 0.0;      ///< the camera head's turn of the picture about the line of sight
  double view_angle_deg = 30.0;  ///< vertical field of view (the zoom)
};

/// The scope fixed for a session: its port, optic, limits and where it starts.
struct LaparoscopeModel {
  Eigen::Vector3d port_W = Eigen::Vector3d::Zero();
  double optic_angle_rad = 0.0;                             ///< θ: 0 or 30° (π/6)
  Eigen::Vector3d horizon_up_W = Eigen::Vector3d::UnitY();  ///< unit: the picture's level up
  /// Distance from the eye to the focal point the camera reports (only the renderer's clipping
  /// and the light's aim use it) [m].
  double focal_distance_m = 0.1;
  double min_insertion_m = 0.005;  ///< the objective just past the port
  double max_insertion_m = 0.2;
  double min_view_angle_deg = 10.0;  ///< zoomed in
  double max_view_angle_deg = 80.0;  ///< zoomed out (a laparoscope's 70-80° field)
  /// The scope pivots at most this far from where it started (the port's and the wall's give).
  double max_pivot_rad = 60.0 * M_PI / 180.0;
  LaparoscopeState home;  ///< the scenario's view: the line of sight through its focal point

  /// From the scenario's camera: port (CameraSpec::port()), optic angle, the insertion that puts
  /// the tip `position_m`'s distance from the port, and the axis and roll aimed so that the line
  /// of sight passes through `focal_point_m` (for 0° optics: the eye is then position_m when the
  /// port is on the line of sight). Refused, naming the field, when the focal point cannot be
  /// seen from the port (it lies within the insertion of it) or the optic cannot be aimed at it.
  static Result<LaparoscopeModel> build(const CameraSpec& camera, const std::string& file = "");
};

/// What the scope shows: the eye, the line of sight and the picture's up; the light at the tip.
struct LaparoscopeView {
  Eigen::Vector3d eye_W = Eigen::Vector3d::Zero();          ///< the objective, at the tip
  Eigen::Vector3d view_dir_W = -Eigen::Vector3d::UnitZ();   ///< unit line of sight
  Eigen::Vector3d up_W = Eigen::Vector3d::UnitY();          ///< unit, ⊥ view_dir_W
  Eigen::Vector3d focal_point_W = Eigen::Vector3d::Zero();  ///< eye + focal distance × view
  Eigen::Vector3d light_W = Eigen::Vector3d::Zero();        ///< the light's exit, at the tip
  double view_angle_deg = 30.0;
};

/// The view for a state (the header's formulas).
[[nodiscard]] LaparoscopeView laparoscope_view(const LaparoscopeModel& model,
                                               const LaparoscopeState& state);

/// The scope's reference "up" r0 for an axis: the horizon's up made perpendicular to the axis
/// (any perpendicular when they are parallel).
[[nodiscard]] Eigen::Vector3d laparoscope_reference_up(const LaparoscopeModel& model,
                                                       const Eigen::Vector3d& axis_W);

/// The scope pivoted about its port: `right_rad` turns the view towards the picture's right,
/// `up_rad` towards its top; kept within max_pivot_rad of home's axis.
void pivot_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double right_rad,
                       double up_rad);
/// In (+) or out (−) through the port, within the insertion limits [m].
void insert_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double delta_m);
/// The scope turned about its axis (the optic with it) [rad], kept in (−π, π].
void roll_laparoscope(LaparoscopeState* state, double delta_rad);
/// The camera head turned: the picture's horizon [rad], kept in (−π, π].
void turn_laparoscope_horizon(LaparoscopeState* state, double delta_rad);
/// Zoom by `factor` (> 1 closer): the view angle's half tangent divided by it, within limits.
void zoom_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state, double factor);

/// Turns the scope about its port so that its line of sight moves `fraction` (0 to 1) of the way
/// towards passing through `target_W` (one step of a fixed-point iteration: rotating the axis by
/// the rotation from the line of sight to the target's direction; the eye, and for θ > 0 r0,
/// move with the axis, so repeated steps converge rather than one landing exactly). The pivot
/// limit applies. Returns the angle left between the line of sight and the target's direction
/// [rad].
double aim_laparoscope(const LaparoscopeModel& model, LaparoscopeState* state,
                       const Eigen::Vector3d& target_W, double fraction);

/// The angle between the line of sight and the direction from the eye to `point_W` [rad].
[[nodiscard]] double laparoscope_off_axis_rad(const LaparoscopeView& view,
                                              const Eigen::Vector3d& point_W);

}  // namespace lap::sim
