#include "haptics/setup/albedo_texture.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "haptics/spatial_hash.h"

namespace lap::haptics {
namespace {

// The integer hash (haptics/spatial_hash.h) is a fixed function of its input, so the images are
// the same bytes on every machine.
uint32_t hash_cell(int32_t i, int32_t j, uint32_t seed) {
  return hash32(static_cast<uint32_t>(i) * 0x9E3779B1U ^ hash32(static_cast<uint32_t>(j) + seed));
}

double unit_hash(uint32_t h) { return static_cast<double>(h & 0xFFFFFFU) / 16777215.0; }

int32_t wrap(int32_t i, int32_t n) { return ((i % n) + n) % n; }

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

using Rgb = Eigen::Vector3d;

Rgb mix(const Rgb& a, const Rgb& b, double t) { return a + (b - a) * std::clamp(t, 0.0, 1.0); }

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Thin bright lines where fbm crosses 0.5: ridged noise, for the fine serosal vessels.
double vessels(double x, double y, int32_t period, uint32_t seed) {
  const double n = tileable_fbm(x, y, period, 3, seed);
  return 1.0 - smoothstep(0.0, 0.012, std::abs(n - 0.5));
}

Rgb albedo(Tissue t, double x, double y, uint32_t seed) {
  switch (t) {
    case Tissue::liver: {
      // Reddish-brown parenchyma seen through the capsule, mottled by the lobules (about 1 mm
      // across, Gray's Anatomy ch. 70): paler cell centres, darker septa between them.
      const double cells = tileable_cells(x, y, 40, seed);
      const double septa = tileable_cell_edge(x, y, 40, seed);
      const double blotch = tileable_fbm(x, y, 4, 4, seed + 11U);
      Rgb c = mix(Rgb(0.52, 0.16, 0.11), Rgb(0.42, 0.12, 0.09), smoothstep(0.1, 0.6, cells));
      c = mix(Rgb(0.33, 0.09, 0.07), c, smoothstep(0.0, 0.15, septa));
      c = mix(c, Rgb(0.58, 0.24, 0.16), 0.5 * smoothstep(0.45, 0.8, blotch));
      return c;
    }
    case Tissue::gallbladder: {
      // Blue-green serosa (bile through a thin wall), whitish patches and fine red vessels.
      const double n = tileable_fbm(x, y, 4, 4, seed);
      Rgb c = mix(Rgb(0.22, 0.42, 0.38), Rgb(0.38, 0.55, 0.48), n);
      c = mix(c, Rgb(0.70, 0.72, 0.64),
              0.35 * smoothstep(0.6, 0.85, tileable_fbm(x, y, 8, 3, seed + 5U)));
      c = mix(c, Rgb(0.55, 0.18, 0.15), 0.7 * vessels(x, y, 3, seed + 9U));
      return c;
    }
    case Tissue::bile_duct: {
      const double n = tileable_fbm(x, y, 6, 4, seed);
      return mix(Rgb(0.80, 0.70, 0.45), Rgb(0.93, 0.86, 0.62), n);
    }
    case Tissue::artery: {
      const double n = tileable_fbm(x, y, 6, 3, seed);
      return mix(Rgb(0.62, 0.22, 0.20), Rgb(0.80, 0.40, 0.35), n);
    }
    case Tissue::clip: {
      // Brushed titanium: fine streaks along one direction.
      const double n =
          0.7 * tileable_fbm(x, 0.37, 64, 2, seed) + 0.3 * tileable_fbm(x, y, 8, 2, seed);
      return mix(Rgb(0.55, 0.56, 0.58), Rgb(0.78, 0.79, 0.80), n);
    }
    case Tissue::duodenum: {
      const double n = tileable_fbm(x, y, 5, 4, seed);
      Rgb c = mix(Rgb(0.72, 0.48, 0.40), Rgb(0.86, 0.62, 0.52), n);
      c = mix(c, Rgb(0.60, 0.20, 0.18), 0.6 * vessels(x, y, 3, seed + 3U));
      return c;
    }
    case Tissue::fat: {
      // Lobulated yellow fat: packed lobules, each a little different, with thin darker septa
      // between them (the cells' borders: where the nearest two feature points are equally
      // near).
      const double edge = tileable_cell_edge(x, y, 14, seed);
      const double n = tileable_fbm(x, y, 4, 3, seed + 7U);
      const double lobule = tileable_value_noise(x, y, 14, seed + 13U);
      Rgb c = mix(Rgb(0.95, 0.82, 0.40), Rgb(0.99, 0.90, 0.55), 0.5 * lobule + 0.5 * n);
      c = mix(Rgb(0.78, 0.58, 0.26), c, smoothstep(0.02, 0.12, edge));
      return c;
    }
    case Tissue::abdominal_wall: {
      // Parietal peritoneum: glistening pale pink with vessels.
      const double n = tileable_fbm(x, y, 4, 4, seed);
      Rgb c = mix(Rgb(0.80, 0.62, 0.58), Rgb(0.92, 0.78, 0.74), n);
      c = mix(c, Rgb(0.65, 0.22, 0.22), 0.6 * vessels(x, y, 2, seed + 1U));
      return c;
    }
  }
  return {1.0, 0.0, 1.0};
}

}  // namespace

std::string_view tissue_name(Tissue t) {
  switch (t) {
    case Tissue::liver:
      return "liver";
    case Tissue::gallbladder:
      return "gallbladder";
    case Tissue::bile_duct:
      return "bile_duct";
    case Tissue::artery:
      return "artery";
    case Tissue::clip:
      return "clip";
    case Tissue::duodenum:
      return "duodenum";
    case Tissue::fat:
      return "fat";
    case Tissue::abdominal_wall:
      return "abdominal_wall";
  }
  return "unknown";
}

double tileable_value_noise(double x, double y, int32_t period, uint32_t seed) {
  const double fx = x * period;
  const double fy = y * period;
  const auto i0 = static_cast<int32_t>(std::floor(fx));
  const auto j0 = static_cast<int32_t>(std::floor(fy));
  const double tx = fade(fx - i0);
  const double ty = fade(fy - j0);
  auto v = [&](int32_t i, int32_t j) {
    return unit_hash(hash_cell(wrap(i, period), wrap(j, period), seed));
  };
  const double a = v(i0, j0) + (v(i0 + 1, j0) - v(i0, j0)) * tx;
  const double b = v(i0, j0 + 1) + (v(i0 + 1, j0 + 1) - v(i0, j0 + 1)) * tx;
  return a + (b - a) * ty;
}

double tileable_fbm(double x, double y, int32_t period, int32_t octaves, uint32_t seed) {
  double sum = 0.0;
  double norm = 0.0;
  double amplitude = 1.0;
  for (int32_t o = 0; o < octaves; ++o) {
    sum += amplitude * tileable_value_noise(x, y, period << o, seed + 101U * o);
    norm += amplitude;
    amplitude *= 0.5;
  }
  return sum / norm;
}

double tileable_cells(double x, double y, int32_t period, uint32_t seed) {
  return tileable_cell_distances(x, y, period, seed).x();
}

double tileable_cell_edge(double x, double y, int32_t period, uint32_t seed) {
  const Eigen::Vector2d d = tileable_cell_distances(x, y, period, seed);
  return d.y() - d.x();
}

Eigen::Vector2d tileable_cell_distances(double x, double y, int32_t period, uint32_t seed) {
  const double fx = x * period;
  const double fy = y * period;
  const auto i0 = static_cast<int32_t>(std::floor(fx));
  const auto j0 = static_cast<int32_t>(std::floor(fy));
  double best = 1e9;
  double second = 1e9;
  for (int32_t dj = -1; dj <= 1; ++dj) {
    for (int32_t di = -1; di <= 1; ++di) {
      const int32_t i = i0 + di;
      const int32_t j = j0 + dj;
      const uint32_t h = hash_cell(wrap(i, period), wrap(j, period), seed);
      const double px = i + 0.15 + 0.7 * unit_hash(h);
      const double py = j + 0.15 + 0.7 * unit_hash(hash32(h));
      const double d = std::hypot(fx - px, fy - py);
      if (d < best) {
        second = best;
        best = d;
      } else {
        second = std::min(second, d);
      }
    }
  }
  return {best, second};
}

RgbImage make_albedo(Tissue t, int32_t size_px, uint32_t seed) {
  RgbImage img;
  img.width = size_px;
  img.height = size_px;
  img.rgb.resize(static_cast<size_t>(size_px) * size_px * 3);
  for (int32_t r = 0; r < size_px; ++r) {
    for (int32_t c = 0; c < size_px; ++c) {
      const Rgb col = albedo(t, (c + 0.5) / size_px, (r + 0.5) / size_px, seed);
      for (int k = 0; k < 3; ++k) {
        img.rgb[(static_cast<size_t>(r) * size_px + c) * 3 + k] =
            static_cast<uint8_t>(std::lround(255.0 * std::clamp(col[k], 0.0, 1.0)));
      }
    }
  }
  return img;
}

}  // namespace lap::haptics
