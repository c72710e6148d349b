#pragma once
/// \file
/// Force shading (thesis §6.1): a continuous normal over a polygonal surface so that stroking a
/// tessellated curved organ feels smooth, while natural edges (the flat ends of a cylinder, the
/// rim of an organ cut) stay sharp.
///
/// Setup: every face corner gets the normal of its vertex *within the face's smoothing group*:
/// the angle-weighted average of the faces around the vertex whose normals are within the
/// crease angle of this face's normal. Faces meeting at more than the crease angle therefore do
/// not blend, and a face that is not shaded (its region switched off) keeps its flat normal.
/// Step: the normal at a contact point (eq. 6-1 for a face: the corner normals weighted by the
/// areas of the three sub-triangles; an edge: the two vertex normals weighted by inverse
/// distance; a vertex: its normal) and the force along it whose magnitude comes from the HIP
/// projected along the shaded normal onto the contacted plane (Figure 6-3).
///
/// The step allocates nothing. Built once per mesh (setup).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/mesh_database.h"

namespace lap::haptics {

class ShadingNormals {
 public:
  /// crease_angle_rad: faces whose normals differ by more do not blend (a natural edge).
  /// face_shaded: per face (database order), 0 = shading off for that face (a region); empty =
  /// all on.
  static ShadingNormals build(const MeshDatabase& mesh, double crease_angle_rad,
                              std::span<const uint8_t> face_shaded = {});

  /// After the mesh deformed (MeshDatabase::set_positions): recomputes the corner normals at
  /// `vertices` — those whose normal may have changed, i.e. every vertex of a face that moved
  /// (MeshUpdateScratch::dirty_vertices) — from the deformed faces, by build()'s rule: a vertex
  /// smooth at rest has every corner take its angle-weighted vertex normal (what build() gives
  /// there, and the database has just recomputed); at a crease each corner blends again the
  /// faces within the crease angle of its own (by their deformed normals); an unshaded face
  /// keeps its flat normal. So a dented organ feels as smooth as it looks (§6.1 over §6.5).
  /// No allocation.
  void update(const MeshDatabase& mesh, std::span<const int32_t> vertices);
  /// The same over the vertices the workspace's last set_positions() recomputed, reading the
  /// faces around each from its flat lists instead of walking fans.
  void update(const MeshDatabase& mesh, const MeshUpdateScratch& scratch);

  /// The shaded unit normal (object frame) at point p on primitive `on` (the point proxy's
  /// contacted primitive). Falls back to the primitive's own normal where it is not smooth.
  [[nodiscard]] Eigen::Vector3d normal(const MeshDatabase& mesh, PrimitiveRef on,
                                       const Eigen::Vector3d& p) const;

  [[nodiscard]] const std::array<Eigen::Vector3d, 3>& corner_normals(int32_t f) const {
    return corners_[f];
  }
  [[nodiscard]] bool shaded(int32_t f) const { return shaded_[f] != 0; }

 private:
  // The normal of corner v of face f blended over the faces at v in f's smoothing group.
  [[nodiscard]] Eigen::Vector3d blended_corner(const MeshDatabase& mesh, int32_t f,
                                               int32_t v) const;

  std::vector<std::array<Eigen::Vector3d, 3>> corners_;  // per face, per corner
  std::vector<uint8_t> shaded_;
  std::vector<uint8_t> smooth_vertex_;  // every corner at the vertex shaded and equal
  std::vector<uint8_t> smooth_edge_;    // both faces shaded, same corner normals at both ends
  double cos_crease_ = 1.0;
};

/// Figure 6-3: the penetration vector to use with the force law when shading is on. `depth` is
/// the HIP's depth under the contacted plane (normal n, unit), `shaded` the shaded unit normal.
/// The HIP is projected along the shaded normal onto the plane: its distance there is
/// depth / (shaded . n). The result points into the object (as HIP - IHIP does).
///
/// Shading smooths the facets' small turns; it "works well when the penetration of HIP is small
/// compared to the size of the polygon" (§6.1). Where the shaded normal stands far from the
/// plane's — a tool pressed deep into a thin rounded edge, or an end held in a crease whose
/// normal is the penetration's, not a face's — it would push sideways with up to 1 / cos times
/// the spring's force, and the two-sided side test flips it as it passes 90°: a force reversing
/// every few ticks (the default patient's liver edge, docs/anatomy.md). So the shaded normal is
/// used in full up to 60° from the plane's (cosine kShadingFullCos), blended towards the plane's
/// up to 75° (kShadingNoneCos) and not used beyond. The normal part is always the depth, the
/// sideways push at most tan 60° times it, and the force continuous in both normals. The angles
/// are this project's choice: a corner normal differs from its face's by less than the crease
/// angle (40° on the shipped liver, the one shaded organ; 30° by default), so on a face contact
/// with a surface at rest every turn that shading exists to smooth is rendered in full. What
/// fades: contacts on a deep dent, and edge and crease contacts, whose plane is not a face's.
/// A crease angle above 60° is faded in part even at rest (scenarios/README.md).
inline constexpr double kShadingFullCos = 0.5;                 // cos 60°
inline constexpr double kShadingNoneCos = 0.2588190451025208;  // cos 75°
[[nodiscard]] inline Eigen::Vector3d shaded_penetration(double depth, const Eigen::Vector3d& n,
                                                        const Eigen::Vector3d& shaded) {
  const double c = shaded.dot(n);
  if (c >= kShadingFullCos) return -(depth / c) * shaded;
  if (c <= kShadingNoneCos) return -depth * n;
  const double w = (c - kShadingNoneCos) / (kShadingFullCos - kShadingNoneCos);
  const Eigen::Vector3d dir = (n + w * (shaded - n)).normalized();
  return -(depth / dir.dot(n)) * dir;
}

}  // namespace lap::haptics
