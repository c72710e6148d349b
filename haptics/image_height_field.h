#pragma once
/// \file
/// Image-based haptic texture (thesis §6.3.3 a): a grey image's texels are heights, mapped onto
/// the object by the two-stage method (Bier & Sloan 1986): (1) S-mapping, the image onto a
/// simple intermediate surface (plane, cylinder, sphere or box) placed in the object's frame;
/// (2) O-mapping, each object point onto that surface, here by projection through the surface's
/// axis or centre (plane: along its normal; cylinder: radially from its axis; sphere: from its
/// centre; box: from its centre onto the face the point's largest coordinate selects).
///
/// The texels are filtered by bicubic Catmull-Rom interpolation, which passes through every texel
/// and is C0 and C1 (§6.3.3 needs both); the image tiles (wraps) in both directions. The gradient
/// is by central differences (eq. 6-5) with step `epsilon_m` on the surface, taken along the
/// intermediate surface's two parameters and carried to the object's axes by the chain rule
/// through the mapping's Jacobian (equal to differencing along x, y, z, eq. 6-6, where the
/// mapping is smooth, at four look-ups instead of six).
///
/// Where the mapping itself is not smooth the field is not either: the poles of the sphere and
/// the edges of the box (documented in haptics/README.md; use a plane or cylinder on organs).
/// The image is decoded by sim/ (no file access here); sample() is allocation-free.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "haptics/height_field.h"

namespace lap::haptics {

/// Grey levels in [0, 1], row-major, row 0 at v = 0.
struct HeightImage {
  int32_t width = 0;
  int32_t height = 0;
  std::vector<float> values;
  [[nodiscard]] float at(int32_t x, int32_t y) const {
    return values[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
};

/// The intermediate surface of the two-stage mapping, in the object's frame.
struct IntermediateSurface {
  enum class Kind : uint8_t { kPlane, kCylinder, kSphere, kBox };
  Kind kind = Kind::kPlane;
  /// Surface frame in the object frame: origin at the centre; z is the plane's normal, the
  /// cylinder's axis, the sphere's pole axis; the box's faces are normal to the frame's axes.
  Eigen::Isometry3d frame_OS = Eigen::Isometry3d::Identity();
  double tile_u_m = 0.01;  ///< plane, box: one image width along u [m]
  double tile_v_m = 0.01;  ///< plane, box: one image height along v; cylinder: along the axis
  int32_t repeat_u = 1;    ///< cylinder, sphere: image repeats around the axis
  int32_t repeat_v = 1;    ///< sphere: image repeats from pole to pole
};

class ImageHeightField final : public HeightField {
 public:
  /// height = amplitude (2 g - 1) for grey level g: mid-grey is the original surface.
  /// epsilon_m: the central-difference step (about half a texel on the surface is right).
  ImageHeightField(HeightImage image, const IntermediateSurface& surface, double amplitude_m,
                   double epsilon_m);
  [[nodiscard]] HeightSample sample(const Eigen::Vector3d& p) const noexcept override;
  /// Catmull-Rom overshoots the texel range by at most 1/8 per axis, hence 1.6 amplitude.
  [[nodiscard]] double max_height_m() const noexcept override { return 1.6 * amplitude_; }

  /// The filtered height at p (object frame).
  [[nodiscard]] double height(const Eigen::Vector3d& p) const noexcept;
  /// Texture coordinates (u, v) of p: one unit per image repeat (the O-mapping).
  [[nodiscard]] Eigen::Vector2d map(const Eigen::Vector3d& p) const noexcept;
  /// Filtered grey level at texture coordinates (u, v).
  [[nodiscard]] double grey(const Eigen::Vector2d& uv) const noexcept;

 private:
  HeightImage image_;
  IntermediateSurface surface_;
  Eigen::Isometry3d frame_SO_;  // object to surface frame
  double amplitude_;
  double epsilon_;
};

}  // namespace lap::haptics
