#pragma once
/// \file
/// An organ's surface properties for the haptic proxies (thesis chapter 6), built from its
/// scenario material at setup: force shading (§6.1), stick-slip friction with its coefficient
/// map (§6.2), and a procedural or image texture (§6.3). §6.6 (no shading with a texture) is
/// already refused by the scenario loader.

#include <memory>

#include "haptics/friction.h"
#include "haptics/haptic_object.h"
#include "haptics/height_field.h"
#include "haptics/shading_normals.h"
#include "sim/setup/scene.h"

namespace lap::sim {

struct OrganSurface {
  std::unique_ptr<haptics::ShadingNormals> shading;
  std::unique_ptr<haptics::HeightField> texture;
  std::unique_ptr<haptics::FrictionModel> friction;
  double texture_k = 1.5;
  /// Points the object's surface-property fields at this surface (which must outlive it) and
  /// sets its force law from the material.
  void apply(const MaterialSpec& material, haptics::HapticObject* object) const;
};

/// Builds what the material asks for; `db` is the organ's database (in the same frame as
/// organ.mesh). The image, if any, was decoded and checked by load_scene.
[[nodiscard]] OrganSurface build_organ_surface(const Organ& organ, const haptics::MeshDatabase& db);

}  // namespace lap::sim
