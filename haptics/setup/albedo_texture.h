#pragma once
/// \file
/// Procedural colour (albedo) images for the generated organs: deterministic, tileable value
/// noise and cellular noise coloured per tissue (the liver's reddish-brown lobular mottling, the
/// gallbladder's blue-green serosa with fine vessels, yellow lobulated fat, the ducts' pale
/// yellow). Tileable because the organs' texture coordinates repeat the image (sampler REPEAT)
/// instead of cutting seams into the closed meshes.

#include <Eigen/Core>
#include <cstdint>
#include <string_view>
#include <vector>

namespace lap::haptics {

/// 8-bit RGB image, rows top to bottom, 3 bytes a pixel.
struct RgbImage {
  int32_t width = 0;
  int32_t height = 0;
  std::vector<uint8_t> rgb;  ///< width * height * 3
};

enum class Tissue : uint8_t {
  liver,
  gallbladder,
  bile_duct,
  artery,
  clip,
  duodenum,
  fat,
  abdominal_wall,
};

/// The tissue's name as used in file names ("liver", "bile_duct", ...).
[[nodiscard]] std::string_view tissue_name(Tissue t);

/// A square, tileable albedo image of the tissue; the same size and seed give the same bytes.
[[nodiscard]] RgbImage make_albedo(Tissue t, int32_t size_px, uint32_t seed = 1);

/// Tileable 2D value noise in [0, 1] at (x, y) in [0, 1)^2 (wraps): `period` lattice cells
/// across, quintic interpolation of hashed lattice values.
[[nodiscard]] double tileable_value_noise(double x, double y, int32_t period, uint32_t seed);
/// Fractal sum of tileable value noise: octaves of doubling period, halving amplitude,
/// normalised to [0, 1].
[[nodiscard]] double tileable_fbm(double x, double y, int32_t period, int32_t octaves,
                                  uint32_t seed);
/// Tileable cellular noise: distance from (x, y) to the nearest of one jittered feature point per
/// cell, in cells (0 on a point, about 0.7 at most), `period` cells across.
[[nodiscard]] double tileable_cells(double x, double y, int32_t period, uint32_t seed);
/// The cells' borders: second-nearest minus nearest feature-point distance (0 on a border).
[[nodiscard]] double tileable_cell_edge(double x, double y, int32_t period, uint32_t seed);
/// Nearest and second-nearest feature-point distances, in cells.
[[nodiscard]] Eigen::Vector2d tileable_cell_distances(double x, double y, int32_t period,
                                                      uint32_t seed);

}  // namespace lap::haptics
