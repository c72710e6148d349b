#pragma once
/// \file
/// The angle atan2(y, x) for y >= 0, as the angle-weighted vertex normals need it (§4.2) for
/// every corner of every face when a mesh deforms. std::atan2 costs about 20 ns; this costs
/// about half as much and agrees with it to within a few units in the last place: the
/// argument is reduced to t in [0, 1], then to d = (t - c) / (1 + t c) with c = k/8 the nearest
/// table point (|d| <= 1/16), and atan(d) is summed to d^15 (truncation below 1e-19).

#include <array>
#include <cmath>

namespace lap::haptics {

namespace detail {
inline const std::array<double, 9>& atan_table() {
  static const std::array<double, 9> table = [] {
    std::array<double, 9> t{};
    for (int k = 0; k <= 8; ++k) t[k] = std::atan(k / 8.0);
    return t;
  }();
  return table;
}

// atan(t) for t in [0, 1].
inline double atan_unit(double t) {
  // t >= 0, so adding 0.5 and truncating rounds to nearest (and compiles to no call).
  const auto k = static_cast<int>(t * 8.0 + 0.5);  // NOLINT(bugprone-incorrect-roundings)
  const double c = k / 8.0;
  const double d = (t - c) / (1.0 + t * c);
  const double d2 = d * d;
  const double series =
      d *
      (1.0 +
       d2 * (-1.0 / 3 +
             d2 * (1.0 / 5 +
                   d2 * (-1.0 / 7 +
                         d2 * (1.0 / 9 + d2 * (-1.0 / 11 + d2 * (1.0 / 13 + d2 * (-1.0 / 15))))))));
  return atan_table()[k] + series;
}
}  // namespace detail

/// atan2(y, x) for y >= 0 (an angle in [0, pi]); y = x = 0 gives 0.
inline double corner_angle(double y, double x) {
  constexpr double kPi = 3.14159265358979323846;
  const double ax = std::abs(x);
  double a = 0.0;
  if (y <= ax) {
    a = ax > 0.0 ? detail::atan_unit(y / ax) : 0.0;
  } else {
    a = 0.5 * kPi - detail::atan_unit(ax / y);
  }
  return x < 0.0 ? kPi - a : a;
}

}  // namespace lap::haptics
