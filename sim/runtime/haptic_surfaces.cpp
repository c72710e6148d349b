#include "sim/runtime/haptic_surfaces.h"

namespace lap::sim {

HapticSurfaces::HapticSurfaces(std::span<const haptics::MeshDatabase* const> dbs,
                               std::span<const haptics::SegmentDatabase* const> segments,
                               std::span<const haptics::ShadingNormals* const> shading) {
  organs_.reserve(dbs.size());
  for (size_t i = 0; i < dbs.size(); ++i) {
    std::vector<Eigen::Vector3d> rest(static_cast<size_t>(dbs[i]->vertex_count()));
    for (int32_t v = 0; v < dbs[i]->vertex_count(); ++v) {
      rest[static_cast<size_t>(v)] = dbs[i]->position(v);
    }
    Organ o{std::make_unique<haptics::MeshDatabase>(*dbs[i]),
            nullptr,
            nullptr,
            nullptr,
            nullptr,
            DeformedSurface(std::move(rest))};
    o.scratch = std::make_unique<haptics::MeshUpdateScratch>(*o.db);
    if (i < segments.size() && segments[i] != nullptr) {
      o.segments = std::make_unique<haptics::SegmentDatabase>(segments[i]->copy_for(*o.db));
      o.segment_scratch = std::make_unique<haptics::SegmentUpdateScratch>(*o.segments);
    }
    if (i < shading.size() && shading[i] != nullptr) {
      o.shading = std::make_unique<haptics::ShadingNormals>(*shading[i]);
    }
    organs_.push_back(std::move(o));
  }
}

void HapticSurfaces::take_up(std::span<const SurfaceDeformation> deformations,
                             int64_t model_steps) noexcept {
  for (size_t i = 0; i < organs_.size() && i < deformations.size(); ++i) {
    Organ& o = organs_[i];
    o.surface.apply_to(deformations[i], {.db = o.db.get(),
                                         .scratch = o.scratch.get(),
                                         .segments = o.segments.get(),
                                         .segment_scratch = o.segment_scratch.get(),
                                         .shading = o.shading.get()});
  }
  model_steps_ = model_steps;
}

int64_t HapticSurfaces::regions_reused() const {
  int64_t n = 0;
  for (const Organ& o : organs_) n += o.scratch->regions_reused;
  return n;
}

int64_t HapticSurfaces::regions_taken_up() const {
  int64_t n = 0;
  for (const Organ& o : organs_) n += o.scratch->regions_reused + o.scratch->regions_updated;
  return n;
}

void HapticSurfaces::point(std::span<haptics::HapticObject> objects) const noexcept {
  for (size_t i = 0; i < organs_.size() && i < objects.size(); ++i) {
    const Organ& o = organs_[i];
    objects[i].mesh = o.db.get();
    objects[i].segments = o.segments.get();
    objects[i].shading = o.shading.get();
  }
}

}  // namespace lap::sim
