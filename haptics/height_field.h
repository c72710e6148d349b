#pragma once
/// \file
/// A haptic texture's height field (thesis §6.3.3): the height above (or below) the original
/// surface at a point of the object, in metres, and its gradient. Heights must be C0 and C1 so
/// that force magnitude and direction (eq. 6-2 to 6-4) stay continuous.
///
/// Implementations: procedural (procedural_textures.h, analytic gradients) and image-based
/// (image_height_field.h, two-stage mapping, gradient by central differences, eq. 6-5).
/// sample() runs in the haptic step: no allocation, no exceptions.

#include <Eigen/Core>

namespace lap::haptics {

/// Height [m] and its gradient (object frame) at one point.
struct HeightSample {
  double height_m = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
};

class HeightField {
 public:
  HeightField() = default;
  HeightField(const HeightField&) = default;
  HeightField& operator=(const HeightField&) = default;
  HeightField(HeightField&&) = default;
  HeightField& operator=(HeightField&&) = default;
  virtual ~HeightField() = default;

  /// Height and gradient at p (object frame, metres).
  [[nodiscard]] virtual HeightSample sample(const Eigen::Vector3d& p) const noexcept = 0;
  /// An upper bound of |height| over the whole field [m]: the band above the surface within
  /// which the texture can be touched before the surface itself (Figure 6-5), and the "h" of the
  /// stabilised mix (eq. 6-4).
  [[nodiscard]] virtual double max_height_m() const noexcept = 0;
};

}  // namespace lap::haptics
