#include "sim/setup/organ_surface.h"

#include <algorithm>
#include <cmath>

#include "haptics/image_height_field.h"
#include "haptics/procedural_textures.h"

namespace lap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

haptics::FrictionCoefficientMap coefficient_map(const FrictionMapSpec& s) {
  haptics::FrictionCoefficientMap m;
  switch (s.kind) {
    case FrictionMapSpec::Kind::kUniform:
      m.kind = haptics::FrictionCoefficientMap::Kind::kUniform;
      break;
    case FrictionMapSpec::Kind::kPeriodic:
      m.kind = haptics::FrictionCoefficientMap::Kind::kPeriodic;
      break;
    case FrictionMapSpec::Kind::kRandom:
      m.kind = haptics::FrictionCoefficientMap::Kind::kRandom;
      break;
  }
  m.period_m = s.period_m;
  m.amplitude = s.amplitude;
  m.grain_m = s.grain_m;
  m.relative_std_dev = s.relative_std_dev;
  m.seed = s.seed;
  return m;
}

std::unique_ptr<haptics::HeightField> image_texture(const Organ& organ,
                                                    const haptics::MeshDatabase& db) {
  const TextureSpec& t = organ.material.texture;
  const haptics::HeightImage& image = *organ.height_image;
  haptics::IntermediateSurface s;
  s.frame_OS = organ.texture_frame_W;
  s.tile_u_m = t.mapping.tile_m[0];
  s.tile_v_m = t.mapping.tile_m[1];
  s.repeat_u = t.mapping.repeat[0];
  s.repeat_v = t.mapping.repeat[1];
  // Half a texel on the surface for the central differences (eq. 6-5).
  double texel = std::min(s.tile_u_m / image.width, s.tile_v_m / image.height);
  using Kind = TextureMappingSpec::Kind;
  switch (t.mapping.kind) {
    case Kind::kPlane:
      s.kind = haptics::IntermediateSurface::Kind::kPlane;
      break;
    case Kind::kBox:
      s.kind = haptics::IntermediateSurface::Kind::kBox;
      break;
    case Kind::kCylinder:
    case Kind::kSphere: {
      // Around the axis a texel spans 2 pi r / (repeat * width), r the mesh's mean distance.
      const Eigen::Isometry3d to_s = s.frame_OS.inverse();
      double r = 0.0;
      for (int32_t v = 0; v < db.vertex_count(); ++v) {
        const Eigen::Vector3d q = to_s * db.position(v);
        r += t.mapping.kind == Kind::kCylinder ? q.head<2>().norm() : q.norm();
      }
      r /= std::max(1, db.vertex_count());
      const double around = 2.0 * kPi * r / (s.repeat_u * image.width);
      if (t.mapping.kind == Kind::kCylinder) {
        s.kind = haptics::IntermediateSurface::Kind::kCylinder;
        texel = std::min(around, s.tile_v_m / image.height);
      } else {
        s.kind = haptics::IntermediateSurface::Kind::kSphere;
        texel = std::min(around, kPi * r / (s.repeat_v * image.height));
      }
      break;
    }
  }
  return std::make_unique<haptics::ImageHeightField>(image, s, t.amplitude_m,
                                                     std::max(1e-7, 0.5 * texel));
}

}  // namespace

OrganSurface build_organ_surface(const Organ& organ, const haptics::MeshDatabase& db) {
  const MaterialSpec& m = organ.material;
  OrganSurface out;
  if (m.shading.enabled) {
    out.shading = std::make_unique<haptics::ShadingNormals>(
        haptics::ShadingNormals::build(db, m.shading.crease_angle_deg * kPi / 180.0));
  }
  if (m.friction_static > 0.0) {
    auto f = std::make_unique<haptics::FrictionModel>();
    f->mu_static = m.friction_static;
    f->mu_dynamic = m.friction_dynamic;
    f->stick_stiffness_n_per_m = m.friction_stick_stiffness_n_per_m > 0.0
                                     ? m.friction_stick_stiffness_n_per_m
                                     : m.stiffness_n_per_m;
    f->slide_stiffness_n_per_m =
        m.friction_slide_stiffness_n_per_m > 0.0
            ? m.friction_slide_stiffness_n_per_m
            : f->stick_stiffness_n_per_m * m.friction_dynamic / m.friction_static;
    f->map = coefficient_map(m.friction_map);
    out.friction = std::move(f);
  }
  const TextureSpec& t = m.texture;
  out.texture_k = t.k_mix;
  if (t.kind == TextureSpec::Kind::kImage && organ.height_image) {
    out.texture = image_texture(organ, db);
  } else if (t.kind == TextureSpec::Kind::kProcedural) {
    if (t.function == "perlin") {
      out.texture = std::make_unique<haptics::PerlinNoise>(t.amplitude_m, t.wavelength_m, t.seed);
    } else if (t.function == "fbm") {
      out.texture = std::make_unique<haptics::FractalNoise>(t.amplitude_m, t.wavelength_m,
                                                            t.octaves, 2.0, 0.5, t.seed);
    } else if (t.function == "worley") {
      out.texture = std::make_unique<haptics::WorleyCells>(t.amplitude_m, t.wavelength_m, t.seed);
    } else if (t.function == "fourier") {
      out.texture = std::make_unique<haptics::FourierSeries>(
          haptics::FourierSeries::sinusoid(t.amplitude_m, t.wavelength_m, t.direction));
    }
  }
  return out;
}

void OrganSurface::apply(const MaterialSpec& material, haptics::HapticObject* object) const {
  object->law.kind = material.damping_n_s_per_m > 0.0 ? haptics::ForceLaw::Kind::kHookeDamped
                                                      : haptics::ForceLaw::Kind::kHooke;
  object->law.stiffness_n_per_m = material.stiffness_n_per_m;
  object->law.damping_n_s_per_m = material.damping_n_s_per_m;
  object->shading = shading.get();
  object->texture = texture.get();
  object->texture_k = texture_k;
  object->friction = friction.get();
}

}  // namespace lap::sim
