#pragma once
/// \file
/// Force of a textured surface (thesis §6.3.1-6.3.2). Header-only, allocation-free.
///
/// - Magnitude: the depth under the *textured* surface, d = h - s, where h is the texture's
///   height at the nearest point of the original surface and s the "nearest distance" of the
///   HIP to it (negative below the original surface, positive above). d <= 0: no collision,
///   whatever the original surface says (Figure 6-5).
/// - Direction: the perturbed normal M = N - grad h + (grad h . N) N (eq. 6-2, bump mapping after
///   Max & Becker), normalised, mixed with the original normal N by eq. 6-4 so that only K h of
///   the penetration is perturbed: F = (d - K h) N + K h M if d >= K h, F = d M otherwise.
///   h in the mix is the texture's height (HeightField::max_height_m), a property of the
///   texture as the thesis has it; it bounds the perturbed part at deep penetration, which is
///   what keeps fine textures stable.

#include <Eigen/Core>

#include "haptics/height_field.h"

namespace lap::haptics {

/// eq. 6-2, normalised. n: unit original normal; gradient: grad h (any frame, same as n).
[[nodiscard]] inline Eigen::Vector3d perturbed_normal(const Eigen::Vector3d& n,
                                                      const Eigen::Vector3d& gradient) {
  const Eigen::Vector3d m = n - gradient + gradient.dot(n) * n;
  const double len = m.norm();
  return len > 0.0 ? Eigen::Vector3d(m / len) : n;
}

/// eq. 6-4 as a penetration vector (pointing into the surface, as HIP - IHIP does) for the force
/// law: depth d >= 0 under the textured surface, kh = K h, n and m unit.
[[nodiscard]] inline Eigen::Vector3d textured_penetration(double d, double kh,
                                                          const Eigen::Vector3d& n,
                                                          const Eigen::Vector3d& m) {
  if (d >= kh) return -((d - kh) * n + kh * m);
  return -d * m;
}

/// §6.3.1 at a contact point q of a textured surface (texture t, K of eq. 6-4), unit outward
/// normal n there and nearest distance s of the probe (negative below the surface): the depth
/// under the textured surface d = h(q) - s, and the penetration of eq. 6-4 (same frame as q and
/// n); zero when the probe is outside the textured surface (d <= 0, Figure 6-5). Both proxies use
/// it.
[[nodiscard]] inline Eigen::Vector3d texture_penetration(const HeightField& t, double texture_k,
                                                         const Eigen::Vector3d& q,
                                                         const Eigen::Vector3d& n, double s) {
  const HeightSample h = t.sample(q);
  const double d = h.height_m - s;
  if (!(d > 0.0)) return Eigen::Vector3d::Zero();
  return textured_penetration(d, texture_k * t.max_height_m(), n, perturbed_normal(n, h.gradient));
}

}  // namespace lap::haptics
