#pragma once
/// \file
/// A deformed organ surface as the modelling loop publishes it (docs/architecture.md: it "publishes
/// surface positions") and as a reader — a copy of the proxies' surfaces (haptic_surfaces.h),
/// the graphics' points — applies it. A deformation lists only the vertices away from rest, with
/// their positions, in arrays sized once for every vertex (so a triple buffer's slots never
/// reallocate); a reader puts back to rest what the previous one moved and learns exactly which
/// vertices changed, whichever snapshots it skipped.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "haptics/shading_normals.h"

namespace lap::sim {

struct SurfaceDeformation {
  int32_t count = 0;                      ///< vertices away from rest: the first `count` entries
  std::vector<int32_t> vertex;            ///< sized to the vertex count
  std::vector<Eigen::Vector3d> position;  ///< world frame [m], sized to the vertex count
  explicit SurfaceDeformation(size_t vertices = 0) : vertex(vertices), position(vertices) {}
};

class DeformedSurface {
 public:
  explicit DeformedSurface(std::vector<Eigen::Vector3d> rest);
  /// Applies a published deformation (no allocation). Returns the vertices whose position
  /// changed, valid until the next call: those the last deformation displaced, in its order,
  /// then those only this one displaces (the same deformation again gives the same list, so the
  /// database's region is kept as it is). A deformation naming a vertex out of range is ignored
  /// for that vertex.
  std::span<const int32_t> apply(const SurfaceDeformation& d) noexcept;
  /// What a reader keeps in step with the surface: the database (required) and its workspace,
  /// and optionally the segment database's edge tree (ray-based rendering, §5.2; its workspace
  /// follows the database workspace's moved set) and the force-shading normals (§6.1).
  struct Targets {
    haptics::MeshDatabase* db = nullptr;
    haptics::MeshUpdateScratch* scratch = nullptr;
    haptics::SegmentDatabase* segments = nullptr;
    haptics::SegmentUpdateScratch* segment_scratch = nullptr;
    haptics::ShadingNormals* shading = nullptr;
  };
  /// apply(), then the targets take up what changed (local refits, no allocation): what a copy
  /// of the proxies' surfaces does with each modelling step (HapticSurfaces::take_up). Returns
  /// whether anything changed (then the scratch's dirty_vertices are the vertices whose normals
  /// were recomputed).
  bool apply_to(const SurfaceDeformation& d, const Targets& t) noexcept;
  [[nodiscard]] std::span<const Eigen::Vector3d> positions() const { return positions_; }

 private:
  std::vector<Eigen::Vector3d> rest_;
  std::vector<Eigen::Vector3d> positions_;
  std::vector<int32_t> displaced_;   // by the last deformation applied
  std::vector<int32_t> displacing_;  // by the one being applied (swapped with displaced_)
  std::vector<int32_t> changed_;
  std::vector<uint8_t> flags_;  // bit 0: in changed_, bit 1: displaced by this call
};

}  // namespace lap::sim
