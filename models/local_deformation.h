#pragma once
/// \file
/// Local deformation of an organ (thesis §6.5, §7.7(1)): a contact at point Pt with penetration
/// vector P moves every vertex V_i within the influence radius R of Pt by w(D_i) P, D_i = |V_i −
/// Pt| on the rest shape, with w(D) = (R − D) / R (the thesis' profile) or the smooth polynomial
/// (1 − (D/R)²)², whose slope is also zero at D = R so the dent has no crease at its rim. Nothing
/// beyond R moves. Several contacts superpose.
///
/// Neighbour lists are precomputed per vertex, as the thesis suggests: the vertices within R + h
/// of it, h the longest edge. The contact point lies on a face, so a vertex of that face is
/// within h of it and its list holds every vertex within R of Pt (triangle inequality): the step
/// visits one list, whatever the mesh size.
///
/// The contact is given on the rest shape: Pt on the rest surface and P, the tool's displacement
/// into the rest surface (object frame). The surface takes `surface_share` s of it (the dent's
/// centre moves s P) and the proxy feels the rest, against the deformed surface (MeshDatabase::
/// set_positions). sim/ gets P from a proxy's contact on the deformed surface (rest_contact): the
/// contact point's place on its primitive mapped back to the rest shape, and P = (point +
/// force / k) − that rest point, i.e. how deep below the deformed surface the force law put the
/// tool (force / k) plus how far that surface is from rest there.
///
/// Felt stiffness: a tool held x into the rest surface (quasi-static, the dent settled, one
/// contact, the surface flat over R) sinks the dent's centre s x and feels k (x − s x): the
/// felt stiffness is (1 − s) k, s being exactly the fraction of the tool's displacement the
/// surface takes. The dent reaches s x in the first step that sees the contact (P is measured
/// against the surface the force was): it does not creep towards it. (Where a vertex's share is
/// more than max_move_per_step_m from where it is, it gets there at that much a call, and the tool
/// feels up to k while it does.) (Had P been force / k alone — the depth below the dented surface
/// — the dent d would settle where d = s (x − d), d = s x / (1 + s), and the tool feel
/// k / (1 + s).) On a coarse mesh with the linear profile the surface between vertices lies a
/// little above the dent's centre, so a contact inside a face feels slightly stiffer.
///
/// Model (immutable: rest shape, lists) apart from state (positions, moved vertices). deform()
/// allocates nothing once the state is sized; it never throws.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "haptics/mesh_database.h"

namespace lap::models {

enum class DeformationProfile : uint8_t {
  kLinear,  ///< (R − D) / R, §6.5
  kSmooth,  ///< (1 − (D/R)²)², C¹ at the rim
};

struct LocalDeformationSettings {
  double radius_m = 0.02;  ///< R
  DeformationProfile profile = DeformationProfile::kLinear;
  /// s: the fraction of the tool's displacement into the rest surface that the dent takes, in
  /// (0, 1); the tool feels (1 − s) k (the header's note). At 1 the surface would give way
  /// entirely and push back with nothing.
  double surface_share = 0.5;
  /// Largest displacement of any vertex [m]: a safety bound against a runaway contact.
  double max_displacement_m = 0.02;
  /// Largest move of a vertex along its rest normal in one call [m], in or out: the surface
  /// follows its contacts at a bounded speed (this over the modelling step; sim/ sets it from a
  /// speed: sim/setup/session_model.cpp, kTissueSurfaceMPerS), so that it neither drops from under
  /// a tool nor springs back onto one by centimetres in one step. 0: no limit (the dent is the
  /// formula at every call).
  double max_move_per_step_m = 0.0;
};

/// One contact, on the rest shape, object frame.
struct DeformationContact {
  Eigen::Vector3d point_O = Eigen::Vector3d::Zero();  ///< Pt, on the rest surface [m]
  /// P: the tool's displacement into the rest surface, from Pt [m]
  Eigen::Vector3d penetration_O = Eigen::Vector3d::Zero();
  int32_t face = -1;  ///< the rest-shape face Pt lies on (its vertices start the search)
  /// The surface conforms to this contact: it takes the full penetration (not surface_share of
  /// it), and conforming contacts combine by the largest displacement at each vertex instead of
  /// adding up. For a body resting in the tissue — the catheter (§7.6.3), whose contacts are
  /// found against the rest shape so the dent cannot feed back on them — whose particles lie a
  /// few millimetres apart within one radius R: summed, their dents would sink the surface many
  /// times deeper than the catheter lies; combined by the largest, the groove meets the
  /// catheter (at max_move_per_step_m a call where that is set).
  bool conform = false;
};

/// A gripper's segment not pressing on this organ (a proxy without a contact on it), object
/// frame: the surface must not pass it. A vertex whose move from where the last call left it goes
/// out of the organ (along its rest normal) and comes within one edge of the segment
/// (`LocalDeformationModel::longest_edge_m`) stops 0.5 mm before its nearest approach to it; so
/// it is held while the segment stays, and a vertex whose nearest approach is where it starts
/// (the segment within that edge, beside or beyond it) does not move out at all. The segment is
/// the ideal proxy as the haptic loop left it (a stretched jaw is a stretched obstacle). Without
/// it a dent's far side, or a dent springing back, moved through a tool that lay just outside
/// (8.1 mm in one modelling step in the hour's soak:
/// docs/benchmarks.md, "Soak"), where the proxy had no contact to be pushed by and no short way
/// out. The hold is without force: the tool, not touching, feels nothing of the tissue it holds
/// back (an open limit). Two narrower rules made the hour's soak worse (docs/benchmarks.md): a
/// stop 0.2 mm past the segment, so that the proxy met the surface as a contact; and letting a
/// move that starts beside or beyond the segment go.
struct DeformationObstacle {
  Eigen::Vector3d a_O = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_O = Eigen::Vector3d::Zero();
};

class LocalDeformationModel {
 public:
  /// Precomputes the neighbour lists. Throws std::invalid_argument naming the bad setting.
  static LocalDeformationModel build(const haptics::MeshDatabase& rest,
                                     const LocalDeformationSettings& settings);

  [[nodiscard]] const LocalDeformationSettings& settings() const { return settings_; }
  [[nodiscard]] int32_t vertex_count() const { return static_cast<int32_t>(rest_.size()); }
  [[nodiscard]] const Eigen::Vector3d& rest_position(int32_t v) const { return rest_[v]; }
  /// Unit, out of the organ: its faces' normals summed by area (zero where they cancel).
  [[nodiscard]] const Eigen::Vector3d& rest_normal(int32_t v) const { return rest_normal_[v]; }
  /// The vertices within R + h of v (the precomputed list).
  [[nodiscard]] std::span<const int32_t> neighbours(int32_t v) const {
    return {neighbour_index_.data() + neighbour_offset_[v],
            static_cast<size_t>(neighbour_offset_[v + 1] - neighbour_offset_[v])};
  }
  [[nodiscard]] const std::array<int32_t, 3>& face_vertices(int32_t f) const {
    return face_vertices_[f];
  }
  [[nodiscard]] int32_t face_count() const { return static_cast<int32_t>(face_vertices_.size()); }
  /// w(D): the weight of the profile at distance D (0 at and beyond R).
  [[nodiscard]] double weight(double distance_m) const;
  [[nodiscard]] double longest_edge_m() const { return longest_edge_; }
  [[nodiscard]] size_t neighbour_entries() const { return neighbour_index_.size(); }

 private:
  LocalDeformationSettings settings_;
  std::vector<Eigen::Vector3d> rest_;                  // n_v x 3 [m], original vertex order
  std::vector<Eigen::Vector3d> rest_normal_;           // n_v x 3, unit (or zero)
  std::vector<std::array<int32_t, 3>> face_vertices_;  // the database's faces (tree order)
  std::vector<int32_t> neighbour_offset_;              // n_v + 1 (CSR)
  std::vector<int32_t> neighbour_index_;               // vertices within R + h, per vertex
  double longest_edge_ = 0.0;                          // h [m]
};

struct LocalDeformationState {
  std::vector<Eigen::Vector3d> positions;   ///< n_v x 3 [m], deformed
  std::vector<int32_t> displaced;           ///< vertices away from rest now
  std::vector<int32_t> changed;             ///< vertices whose position the last call changed
  std::vector<uint8_t> flags;               ///< n_v: bit 0 displaced, bit 1 changed (scratch)
  std::vector<Eigen::Vector3d> conforming;  ///< n_v: the largest conforming displacement (scratch)
  std::vector<Eigen::Vector3d> previous;    ///< n_v: the positions the last call left
  int32_t clamped = 0;  ///< vertices held at max_displacement_m (before the speed limit), last call
  int32_t stopped = 0;  ///< vertices stopped at an obstacle, last call
  int32_t slowed = 0;   ///< vertices held to max_move_per_step_m, last call
  double deepest_m = 0.0;  ///< largest displacement of any vertex from rest, last call [m]
  /// Sized and at rest for a model (setup; allocates).
  explicit LocalDeformationState(const LocalDeformationModel& model);
};

/// The contact, on the rest shape, of a force pushing on the deformed surface (a proxy's contact;
/// a catheter's reaction, §7.6.3): the point keeps its barycentric place on its primitive, mapped
/// from the deformed positions to the rest ones, and the penetration is where the force law puts
/// the tool — the point plus force / stiffness (the organ's haptic stiffness) — measured from
/// that rest point: the tool's displacement into the rest surface, so that the dent takes
/// surface_share of it (the header's felt stiffness). A point on the rest surface (the
/// catheter's contacts, found there) gives force / stiffness.
[[nodiscard]] DeformationContact rest_contact(const LocalDeformationModel& model,
                                              const haptics::MeshDatabase& deformed,
                                              haptics::PrimitiveRef primitive,
                                              const Eigen::Vector3d& point_O,
                                              const Eigen::Vector3d& force_O,
                                              double stiffness_n_per_m) noexcept;

/// The same with the deformed positions given as an array (vertex order) and `topology` any
/// database of the organ (rest or deformed: only its faces and edges are read) — for the
/// modelling loop, which keeps positions but not a deformed database.
[[nodiscard]] DeformationContact rest_contact(const LocalDeformationModel& model,
                                              const haptics::MeshDatabase& topology,
                                              std::span<const Eigen::Vector3d> deformed_positions,
                                              haptics::PrimitiveRef primitive,
                                              const Eigen::Vector3d& point_O,
                                              const Eigen::Vector3d& force_O,
                                              double stiffness_n_per_m) noexcept;

/// Recomputes the deformed shape from the rest shape and the given contacts (no contact: back to
/// rest), each vertex then held to max_move_per_step_m along its rest normal and stopped at the
/// obstacles on its way from where the last call left it (so with either the result depends on
/// that too). Afterwards `changed` lists every vertex whose position changed since the previous
/// call (what MeshDatabase::set_positions(positions, changed) needs) and `deepest_m` the largest
/// displacement. A contact that is not finite or names no face makes the call return false and
/// leave the surface at rest (`changed` then lists the vertices that went back). `obstacles`: the
/// grippers' segments the surface must not pass (DeformationObstacle); a non-finite one is
/// ignored.
bool deform(const LocalDeformationModel& model, std::span<const DeformationContact> contacts,
            LocalDeformationState* state,
            std::span<const DeformationObstacle> obstacles = {}) noexcept;

}  // namespace lap::models
