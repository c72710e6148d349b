#pragma once
/// \file
/// Contacts between the catheter and the other deformables (thesis §7.6.3, Figure 7-19): the
/// catheter's centre-line particles against a surface (an organ, or the duct's inner wall), each
/// kept the catheter's radius (plus, for the duct's mid-surface, half its wall) away from it.
/// Each particle tracks its nearest primitive by the point proxy's local search (Neighborhood
/// Watch, §4.3) from one modelling step to the next, so the cost does not depend on the surface's
/// size. A particle beyond the surface's bounding box (grown by its clearance) cannot touch it
/// and is not searched at all — most particles, for most surfaces; when it comes back, its
/// nearest face is found afresh by the surface's tree (exact), as at setup, not walked to from
/// where it was left.
///
/// A particle closer than its clearance gets a contact plane in the catheter state (a spring
/// along the surface normal inside the catheter's implicit step), and its reaction — equal and
/// opposite — is reported for the surface's model (local deformation, the duct's modes).
///
/// The search allocates nothing and never throws.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/mesh_database.h"
#include "models/catheter_model.h"
#include "models/local_deformation.h"

namespace lap::models {

struct SurfaceContactSettings {
  double clearance_m = 0.00125;  ///< the catheter's radius (+ half a shell's wall)
  double stiffness_n_per_m = 100.0;
  double damping_n_s_per_m = 0.005;
  /// Coulomb friction along the surface, μ (0: none): the catheter sliding in the duct's lumen
  /// or over an organ (catheter_model.h regularises it). The surface is taken at rest; a moving
  /// one sets CatheterState::contact_surface_velocity after the search.
  double friction_coefficient = 0.0;
  /// The surface is touched from its back (the inside of a tube whose normals point out).
  bool from_inside = false;
  /// Each particle is kept on the side of the surface it is on (an open tube touched from within
  /// and from without): the side is found at setup and changes only past an open rim.
  bool keep_side = false;
};

/// Per particle, the nearest primitive found last time (object frame of the surface).
struct SurfaceTracking {
  std::vector<haptics::PrimitiveRef> nearest;
  std::vector<int8_t> side;   ///< +1 in front of the surface, −1 behind (keep_side)
  std::vector<uint8_t> away;  ///< 1: beyond the surface's box last step (nearest is stale)
  /// The nearest face of every particle, by the surface's tree (setup).
  SurfaceTracking(const haptics::MeshDatabase& surface, const Eigen::Isometry3d& pose_WO,
                  const CatheterState& catheter);
};

/// One contact's reaction on the surface.
struct SurfaceReaction {
  int32_t particle = -1;
  haptics::PrimitiveRef primitive;
  Eigen::Vector3d point_O = Eigen::Vector3d::Zero();             ///< nearest point, object frame
  Eigen::Vector3d force_on_surface_W = Eigen::Vector3d::Zero();  ///< [N]
};

/// Tracks every particle and sets (or clears) its contact plane for this surface; writes the
/// reactions (the spring force at the current positions, negated) into `out` and returns how
/// many (at most out.size()). Call once per surface per modelling step, before step_catheter;
/// with several surfaces, the last one touching a particle sets its plane.
/// `open_faces` (one per face of the mesh the surface was built from, in its order, or empty)
/// marks faces cut open (the duct's incision): a particle
/// over them meets no wall, and their rim is passed as an open surface's boundary is.
int32_t update_surface_contacts(const haptics::MeshDatabase& surface,
                                const Eigen::Isometry3d& pose_WO,
                                const SurfaceContactSettings& settings, SurfaceTracking* tracking,
                                CatheterState* catheter, std::span<SurfaceReaction> out,
                                std::span<const uint8_t> open_faces = {}) noexcept;

/// After step_catheter: the reactions become the contact springs' forces at the step's end
/// (what the implicit step applied to the catheter, negated, never pulling) and the friction
/// the step applied along the surface, negated, so both sides of every contact see the same
/// force.
void settle_reactions(const CatheterState& catheter, std::span<SurfaceReaction> reactions) noexcept;

/// The dents the catheter makes in a locally deformed organ (`model`; §6.5, §7.6.3). The
/// contacts must have been tracked against the organ's rest surface (`rest`: a database that is
/// never deformed), not the dented one: a catheter that saw its own dent would lose the contact
/// and the dent with it, every other step. Each settled reaction becomes a conforming contact
/// (local_deformation.h) pressed reaction / stiffness deep, so the drawn groove meets the
/// catheter and the organ's spring carries it. Writes at most out.size(); returns how many.
int32_t catheter_dents(const LocalDeformationModel& model, const haptics::MeshDatabase& rest,
                       const Eigen::Isometry3d& pose_WO, double stiffness_n_per_m,
                       std::span<const SurfaceReaction> reactions,
                       std::span<DeformationContact> out) noexcept;

/// Clears every particle's contact plane (before the surfaces set them again).
void clear_contacts(CatheterState* catheter) noexcept;

}  // namespace lap::models
