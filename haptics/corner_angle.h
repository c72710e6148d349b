#pragma once
/// \file
/// The angle atan2(y, x) for y >= 0, as the angle-weighted vertex normals need it (§4.2) for
/// every corner of every face when a mesh deforms. std::atan2 costs about 20 ns; this costs
/// less and agrees with it to within a few units in the last place: the argument is reduced to
/// t in [0, 1], then to d = (t - c) / (1 + t c) with c = k/64 the nearest table point
/// (|d| <= 1/128), and atan(d) is summed to d^7 (truncation below 1e-20): a short chain of
/// dependent multiplications, which is what the cost is made of.

#include <array>
#include <cmath>

namespace lap::haptics {

namespace detail {
inline constexpr int kAtanSteps = 64;
inline const std::array<double, kAtanSteps + 1>& atan_table() {
  static const std::array<double, kAtanSteps + 1> table = [] {
    std::array<double, kAtanSteps + 1> t{};
    for (int k = 0; k <= kAtanSteps; ++k) t[k] = std::atan(static_cast<double>(k) / kAtanSteps);
    return t;
  }();
  return table;
}

// atan(t) for t in [0, 1].
inline double atan_unit(double t) {
  // t >= 0, so adding 0.5 and truncating rounds to nearest (and compiles to no call).
  const auto k = static_cast<int>(t * kAtanSteps + 0.5);  // NOLINT(bugprone-incorrect-roundings)
  const double c = static_cast<double>(k) / kAtanSteps;
  const double d = (t - c) / (1.0 + t * c);
  const double d2 = d * d;
  const double series = d * (1.0 + d2 * (-1.0 / 3 + d2 * (1.0 / 5 + d2 * (-1.0 / 7))));
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
