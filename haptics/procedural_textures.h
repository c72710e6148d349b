#pragma once
/// \file
/// Procedural haptic textures (thesis §6.3.3 b): solid height fields h(x, y, z) evaluated at the
/// contact point in the object's frame, each with its analytic gradient. All are C1 (Perlin's
/// quintic fade is C2; the Worley field uses a smooth minimum, see WorleyCells).
///
/// Built once (setup, may compute tables); sample() is allocation-free.

#include <array>
#include <cstdint>

#include "haptics/height_field.h"

namespace lap::haptics {

/// Improved gradient noise (Perlin 1985/2002): height = amplitude * noise(p / wavelength).
class PerlinNoise final : public HeightField {
 public:
  PerlinNoise(double amplitude_m, double wavelength_m, uint32_t seed = 1);
  [[nodiscard]] HeightSample sample(const Eigen::Vector3d& p) const noexcept override;
  [[nodiscard]] double max_height_m() const noexcept override { return kBound * amplitude_; }
  /// Unit-amplitude noise at q (in wavelengths) and its gradient with respect to q.
  [[nodiscard]] double noise(const Eigen::Vector3d& q, Eigen::Vector3d* gradient) const noexcept;
  /// The gradient vector at lattice point (x, y, z) (cells taken modulo 256), one of the 12
  /// cube-edge directions: noise is the sum over the 8 corners c of the point's cell of
  /// fade-weights times lattice_gradient(c) . (q - c) (Perlin 2002).
  [[nodiscard]] Eigen::Vector3d lattice_gradient(int64_t x, int64_t y, int64_t z) const noexcept;
  /// The lattice's hash table (Perlin's permutation, doubled): FractalNoise evaluates its octaves
  /// with it several at a time.
  [[nodiscard]] const std::array<uint8_t, 512>& permutation() const noexcept { return perm_; }
  /// |noise| stays below this (checked by a test over many samples).
  static constexpr double kBound = 1.1;

 private:
  double amplitude_;
  double inv_wavelength_;
  std::array<uint8_t, 512> perm_{};
};

/// Fractal sum (fBm) of Perlin octaves: sum over o of gain^o noise(lacunarity^o p / wavelength),
/// times amplitude (Ebert et al. 1994).
class FractalNoise final : public HeightField {
 public:
  static constexpr int kMaxOctaves = 8;
  FractalNoise(double amplitude_m, double wavelength_m, int octaves = 4, double lacunarity = 2.0,
               double gain = 0.5, uint32_t seed = 1);
  [[nodiscard]] HeightSample sample(const Eigen::Vector3d& p) const noexcept override;
  [[nodiscard]] double max_height_m() const noexcept override { return max_height_; }

 private:
  PerlinNoise base_;
  int octaves_;
  double max_height_;
  // Per octave (setup): amplitude gain^o, spatial scale lacunarity^o / wavelength, offset.
  std::array<double, kMaxOctaves> octave_amplitude_{};
  std::array<double, kMaxOctaves> octave_scale_{};
  std::array<Eigen::Vector3d, kMaxOctaves> octave_offset_{};
};

/// Worley's cellular texture (1996): one jittered feature point per cubic cell of side
/// `cell_m`; F1^2 (squared distance to the nearest feature point, in cells) replaced by the
/// smooth minimum m = -ln(sum exp(-k d_i^2)) / k over the 27 neighbouring cells, so the ridges
/// between cells are rounded and the field is C1. height = amplitude (2 exp(-m / w) - 1):
/// domes of height `amplitude` on the feature points, valleys of -amplitude between them.
class WorleyCells final : public HeightField {
 public:
  WorleyCells(double amplitude_m, double cell_m, uint32_t seed = 1);
  [[nodiscard]] HeightSample sample(const Eigen::Vector3d& p) const noexcept override;
  [[nodiscard]] double max_height_m() const noexcept override { return max_height_; }
  static constexpr double kSharpness = 64.0;  ///< k [1/cell^2]
  static constexpr double kWidth = 0.1;       ///< w [cell^2]

 private:
  double amplitude_;
  double inv_cell_;
  uint32_t seed_;
  double max_height_;
};

/// A Fourier series of plane waves: h = sum a_j sin(2 pi k_j . p + phi_j).
class FourierSeries final : public HeightField {
 public:
  static constexpr int kMaxTerms = 8;
  struct Term {
    double amplitude_m = 0.0;
    Eigen::Vector3d wave_vector_per_m = Eigen::Vector3d::Zero();  ///< k_j [1/m]
    double phase_rad = 0.0;
  };
  FourierSeries() = default;
  /// Adds a term; returns false (and adds nothing) beyond kMaxTerms.
  bool add(const Term& term);
  /// The single sinusoid amplitude sin(2 pi (p . direction) / wavelength).
  static FourierSeries sinusoid(double amplitude_m, double wavelength_m,
                                const Eigen::Vector3d& direction);
  [[nodiscard]] HeightSample sample(const Eigen::Vector3d& p) const noexcept override;
  [[nodiscard]] double max_height_m() const noexcept override { return max_height_; }

 private:
  std::array<Term, kMaxTerms> terms_{};
  int count_ = 0;
  double max_height_ = 0.0;
};

}  // namespace lap::haptics
