#pragma once
/// \file
/// The organs' surfaces as the haptic loop's proxies read them — per organ its database
/// (§4.2), its segment database (§5.2) and its force-shading normals (§6.1) — as one of three
/// copies. The modelling thread brings a copy up to date with each step's deformations (§6.5:
/// normals and trees refitted where the surface moved, over a region each copy keeps from one
/// take-up to the next) and passes it to the haptic thread
/// through a triple buffer; the haptic step only points its objects at the newest copy. So the
/// haptic step never refits a tree or recomputes a normal (that costs a few hundred
/// microseconds when three organs are dented at once), and it never waits (docs/architecture.md:
/// lock-free snapshots).
///
/// A copy remembers what it last took up (DeformedSurface), so it is exact whichever steps it
/// missed while the haptic thread held it.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "haptics/haptic_object.h"
#include "haptics/mesh_database.h"
#include "haptics/segment_database.h"
#include "haptics/shading_normals.h"
#include "sim/runtime/deformed_surface.h"

namespace lap::sim {

class HapticSurfaces {
 public:
  /// Copies of the organs' databases at rest (`shading[i]` null: organ i not shaded). Setup.
  HapticSurfaces(std::span<const haptics::MeshDatabase* const> dbs,
                 std::span<const haptics::SegmentDatabase* const> segments,
                 std::span<const haptics::ShadingNormals* const> shading);

  /// Takes up the modelling step's deformations (one per organ) and remembers the step. No
  /// allocation, no exception.
  void take_up(std::span<const SurfaceDeformation> deformations, int64_t model_steps) noexcept;

  /// Points each object at this copy's database, segment database and shading normals (the
  /// objects' other fields — force law, texture, friction — are left as they are).
  void point(std::span<haptics::HapticObject> objects) const noexcept;

  [[nodiscard]] int32_t organ_count() const { return static_cast<int32_t>(organs_.size()); }
  /// Organ o's vertices as this copy has them (world frame).
  [[nodiscard]] std::span<const Eigen::Vector3d> positions(int32_t o) const {
    return organs_[static_cast<size_t>(o)].surface.positions();
  }
  [[nodiscard]] const haptics::MeshDatabase& db(int32_t o) const {
    return *organs_[static_cast<size_t>(o)].db;
  }
  /// The modelling step this copy shows.
  [[nodiscard]] int64_t model_steps() const { return model_steps_; }
  /// Take-ups of a surface so far whose moved vertices were those of its last take-up (a dent
  /// held still: the region kept from the last take-up is used as it is), of all take-ups that
  /// moved something (the others change the region by what started or stopped moving).
  [[nodiscard]] int64_t regions_reused() const;
  [[nodiscard]] int64_t regions_taken_up() const;

 private:
  struct Organ {
    std::unique_ptr<haptics::MeshDatabase> db;
    std::unique_ptr<haptics::SegmentDatabase> segments;  // null: none
    std::unique_ptr<haptics::ShadingNormals> shading;    // null: not shaded
    std::unique_ptr<haptics::MeshUpdateScratch> scratch;
    std::unique_ptr<haptics::SegmentUpdateScratch> segment_scratch;
    DeformedSurface surface;
  };
  std::vector<Organ> organs_;
  int64_t model_steps_ = 0;
};

}  // namespace lap::sim
