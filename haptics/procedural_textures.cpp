#include "haptics/procedural_textures.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "haptics/spatial_hash.h"

namespace lap::haptics {
namespace {

// The 32-byte vectors below (Lanes) are internal: no ABI to keep for them (GCC reports the
// warning at the end of the file, so it stays off for the rest of it).
#pragma GCC diagnostic ignored "-Wpsabi"

constexpr double kTwoPi = 6.283185307179586;

// Quintic fade 6t^5 - 15t^4 + 10t^3 and its derivative (Perlin 2002): C2 across cells.
template <typename T>
[[gnu::always_inline]] inline T fade(const T& t) {
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}
template <typename T>
[[gnu::always_inline]] inline T dfade(const T& t) {
  return 30.0 * t * t * (t * (t - 2.0) + 1.0);
}

// The 12 cube-edge gradient directions, padded to 16 (Perlin 2002).
constexpr std::array<std::array<double, 3>, 16> kGradients = {{{1, 1, 0},
                                                               {-1, 1, 0},
                                                               {1, -1, 0},
                                                               {-1, -1, 0},
                                                               {1, 0, 1},
                                                               {-1, 0, 1},
                                                               {1, 0, -1},
                                                               {-1, 0, -1},
                                                               {0, 1, 1},
                                                               {0, -1, 1},
                                                               {0, 1, -1},
                                                               {0, -1, -1},
                                                               {1, 1, 0},
                                                               {-1, 1, 0},
                                                               {0, -1, 1},
                                                               {0, -1, -1}}};

// Up to four points' noise at once (the fractal's octaves), where the CPU has AVX2: GCC's vector
// extension. Every lane goes through the operations noise() does for one point, in the same
// order and without fused multiply-adds (AVX2 does not bring FMA), so each lane rounds exactly as
// the one-point code: the results are the same bits with and without it. These functions are
// inlined into one caller per instruction set.
using Lanes = double __attribute__((vector_size(32)));
constexpr int kLaneCount = 4;

[[gnu::always_inline]] inline double lane(double v, int /*l*/) { return v; }
[[gnu::always_inline]] inline double lane(const Lanes& v, int l) { return v[l]; }

// Perlin's noise and its gradient at kN points given by their coordinates qx, qy, qz (T is
// double for one point, Lanes for up to four): the cell found by truncation (std::floor is a libm
// call on baseline x86-64; exact for |q| < 2^63), the corners' hashes perm[perm[perm[x + i] + y +
// j] + z + k] with the shared lookups once, the eight corners in the order c = i + 2 j + 4 k.
template <int kN, typename T>
[[gnu::always_inline]] inline void perlin_at(const std::array<uint8_t, 512>& perm, const T& qx,
                                             const T& qy, const T& qz, T* n_out, T* gx_out,
                                             T* gy_out, T* gz_out) noexcept {
  const auto cell_floor = [](double t) {
    const auto i = static_cast<int64_t>(t);
    return t < static_cast<double>(i) ? i - 1 : i;
  };
  std::array<int, kN> xi{};
  std::array<int, kN> zi{};
  std::array<std::array<int, 2>, kN> row{};
  T rx{};
  T ry{};
  T rz{};
  for (int l = 0; l < kN; ++l) {
    const int64_t ix = cell_floor(lane(qx, l));
    const int64_t iy = cell_floor(lane(qy, l));
    const int64_t iz = cell_floor(lane(qz, l));
    // Cells repeat every 256 (the table's period), far beyond any organ at these wavelengths.
    xi[l] = static_cast<int>(ix & 255);
    const auto yi = static_cast<int>(iy & 255);
    zi[l] = static_cast<int>(iz & 255);
    row[l] = {perm[xi[l]] + yi, perm[xi[l] + 1] + yi};
    if constexpr (kN == 1) {
      rx = qx - static_cast<double>(ix);
      ry = qy - static_cast<double>(iy);
      rz = qz - static_cast<double>(iz);
    } else {
      rx[l] = lane(qx, l) - static_cast<double>(ix);
      ry[l] = lane(qy, l) - static_cast<double>(iy);
      rz[l] = lane(qz, l) - static_cast<double>(iz);
    }
  }
  const T fx = fade(rx);
  const T fy = fade(ry);
  const T fz = fade(rz);
  const T dx = dfade(rx);
  const T dy = dfade(ry);
  const T dz = dfade(rz);
  T n{};
  T gx{};
  T gy{};
  T gz{};
  const auto corner = [&]<int c>() __attribute__((always_inline)) {
    constexpr int i = c & 1;
    constexpr int j = (c >> 1) & 1;
    constexpr int k = (c >> 2) & 1;
    T g0{};
    T g1{};
    T g2{};
    for (int l = 0; l < kN; ++l) {
      const auto& grad = kGradients[perm[perm[row[l][i] + j] + zi[l] + k] & 15];
      if constexpr (kN == 1) {
        g0 = grad[0];
        g1 = grad[1];
        g2 = grad[2];
      } else {
        g0[l] = grad[0];
        g1[l] = grad[1];
        g2[l] = grad[2];
      }
    }
    const T value = g0 * (rx - i) + g1 * (ry - j) + g2 * (rz - k);
    T wx{};
    T wy{};
    T wz{};
    T sx{};
    T sy{};
    T sz{};
    if constexpr (i != 0) {
      wx = fx;
      sx = dx;
    } else {
      wx = 1.0 - fx;
      sx = -dx;
    }
    if constexpr (j != 0) {
      wy = fy;
      sy = dy;
    } else {
      wy = 1.0 - fy;
      sy = -dy;
    }
    if constexpr (k != 0) {
      wz = fz;
      sz = dz;
    } else {
      wz = 1.0 - fz;
      sz = -dz;
    }
    const T weight = wx * wy * wz;
    n += weight * value;
    gx += weight * g0 + value * (sx * wy * wz);
    gy += weight * g1 + value * (wx * sy * wz);
    gz += weight * g2 + value * (wx * wy * sz);
  };
  [&]<int... c>(std::integer_sequence<int, c...>) __attribute__((always_inline)) {
    (corner.template operator()<c>(), ...);
  }
  (std::make_integer_sequence<int, 8>{});
  *n_out = n;
  *gx_out = gx;
  *gy_out = gy;
  *gz_out = gz;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define LAP_FRACTAL_LANES 1
// The octaves q[0, count) four at a time with AVX2 (the caller checks the CPU has it); those left
// over one at a time (a lane costs its hash lookups whether its result is used or not).
__attribute__((target("avx2"))) void octaves_avx2(const std::array<uint8_t, 512>& perm,
                                                  const Eigen::Vector3d* q, int count, double* n,
                                                  Eigen::Vector3d* g) noexcept {
  int first = 0;
  for (; first + kLaneCount <= count; first += kLaneCount) {
    Lanes qx{};
    Lanes qy{};
    Lanes qz{};
    for (int l = 0; l < kLaneCount; ++l) {
      qx[l] = q[first + l].x();
      qy[l] = q[first + l].y();
      qz[l] = q[first + l].z();
    }
    Lanes ln{};
    Lanes lx{};
    Lanes ly{};
    Lanes lz{};
    perlin_at<kLaneCount>(perm, qx, qy, qz, &ln, &lx, &ly, &lz);
    for (int l = 0; l < kLaneCount; ++l) {
      n[first + l] = ln[l];
      g[first + l] = {lx[l], ly[l], lz[l]};
    }
  }
  for (; first < count; ++first) {
    double gx = 0.0;
    double gy = 0.0;
    double gz = 0.0;
    perlin_at<1>(perm, q[first].x(), q[first].y(), q[first].z(), &n[first], &gx, &gy, &gz);
    g[first] = {gx, gy, gz};
  }
}
#endif

}  // namespace

PerlinNoise::PerlinNoise(double amplitude_m, double wavelength_m, uint32_t seed)
    : amplitude_(amplitude_m), inv_wavelength_(1.0 / wavelength_m) {
  std::array<uint8_t, 256> p{};
  for (int i = 0; i < 256; ++i) p[i] = static_cast<uint8_t>(i);
  uint32_t h = hash32(seed + 0x51ed270bU);
  for (int i = 255; i > 0; --i) {  // Fisher-Yates with a hashed sequence: one table per seed
    h = hash32(h + static_cast<uint32_t>(i));
    std::swap(p[i], p[h % static_cast<uint32_t>(i + 1)]);
  }
  for (int i = 0; i < 512; ++i) perm_[i] = p[i & 255];
}

double PerlinNoise::noise(const Eigen::Vector3d& q, Eigen::Vector3d* gradient) const noexcept {
  double n = 0.0;
  double gx = 0.0;
  double gy = 0.0;
  double gz = 0.0;
  perlin_at<1>(perm_, q.x(), q.y(), q.z(), &n, &gx, &gy, &gz);
  if (gradient != nullptr) *gradient = {gx, gy, gz};
  return n;
}

Eigen::Vector3d PerlinNoise::lattice_gradient(int64_t x, int64_t y, int64_t z) const noexcept {
  const int xi = static_cast<int>(x & 255);
  const int yi = static_cast<int>(y & 255);
  const int zi = static_cast<int>(z & 255);
  const auto& g = kGradients[static_cast<size_t>(perm_[perm_[perm_[xi] + yi] + zi] & 15)];
  return {g[0], g[1], g[2]};
}

HeightSample PerlinNoise::sample(const Eigen::Vector3d& p) const noexcept {
  Eigen::Vector3d g;
  const double n = noise(p * inv_wavelength_, &g);
  return {amplitude_ * n, (amplitude_ * inv_wavelength_) * g};
}

FractalNoise::FractalNoise(double amplitude_m, double wavelength_m, int octaves, double lacunarity,
                           double gain, uint32_t seed)
    : base_(1.0, 1.0, seed), octaves_(std::clamp(octaves, 1, kMaxOctaves)) {
  double sum = 0.0;
  double a = 1.0;
  for (int o = 0; o < octaves_; ++o, a *= gain) sum += std::abs(a);
  // The octaves' factors by the same products as a running loop would form them.
  double amplitude = amplitude_m;
  double scale = 1.0 / wavelength_m;
  for (int o = 0; o < octaves_; ++o, amplitude *= gain, scale *= lacunarity) {
    octave_amplitude_[o] = amplitude;
    octave_scale_[o] = scale;
    // Each octave shifted so the octaves' lattices do not line up at the origin.
    octave_offset_[o] = Eigen::Vector3d(17.13 * o, 31.71 * o, 7.37 * o);
  }
  max_height_ = PerlinNoise::kBound * amplitude_m * sum;
}

HeightSample FractalNoise::sample(const Eigen::Vector3d& p) const noexcept {
  std::array<Eigen::Vector3d, kMaxOctaves> q;
  q.fill(Eigen::Vector3d::Zero());
  for (int o = 0; o < octaves_; ++o) q[o] = p * octave_scale_[o] + octave_offset_[o];
  std::array<double, kMaxOctaves> n{};
  std::array<Eigen::Vector3d, kMaxOctaves> g;
#ifdef LAP_FRACTAL_LANES
  // The same bits either way (octaves_avx2); four octaves at once save ~40 % of the sample.
  if (__builtin_cpu_supports("avx2")) {
    octaves_avx2(base_.permutation(), q.data(), octaves_, n.data(), g.data());
  } else
#endif
  {
    for (int o = 0; o < octaves_; ++o) n[o] = base_.noise(q[o], &g[o]);
  }
  double height = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  for (int o = 0; o < octaves_; ++o) {
    height += octave_amplitude_[o] * n[o];
    gradient += (octave_amplitude_[o] * octave_scale_[o]) * g[o];
  }
  return {height, gradient};
}

WorleyCells::WorleyCells(double amplitude_m, double cell_m, uint32_t seed)
    : amplitude_(amplitude_m), inv_cell_(1.0 / cell_m), seed_(seed) {
  // The smooth minimum undershoots the true F1^2 by at most ln(27) / k.
  max_height_ = amplitude_ * (2.0 * std::exp(std::log(27.0) / (kSharpness * kWidth)) - 1.0);
}

HeightSample WorleyCells::sample(const Eigen::Vector3d& p) const noexcept {
  const Eigen::Vector3d q = p * inv_cell_;
  const Eigen::Vector3d base(std::floor(q.x()), std::floor(q.y()), std::floor(q.z()));
  const auto bx = static_cast<uint32_t>(static_cast<int64_t>(base.x()));
  const auto by = static_cast<uint32_t>(static_cast<int64_t>(base.y()));
  const auto bz = static_cast<uint32_t>(static_cast<int64_t>(base.z()));
  std::array<double, 27> d2{};
  std::array<Eigen::Vector3d, 27> offset{};
  double d2_min = 1e300;
  int n = 0;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        // One hash per cell; its three 10-bit fields place the feature point in the cell.
        const uint32_t h = hash32(((bx + static_cast<uint32_t>(dx)) * 0x8da6b343U) ^
                                  ((by + static_cast<uint32_t>(dy)) * 0xd8163841U) ^
                                  ((bz + static_cast<uint32_t>(dz)) * 0xcb1ab31fU) ^ seed_);
        const Eigen::Vector3d jitter(((h & 0x3FFU) + 0.5) / 1024.0,
                                     (((h >> 10U) & 0x3FFU) + 0.5) / 1024.0,
                                     (((h >> 20U) & 0x3FFU) + 0.5) / 1024.0);
        offset[n] = q - (base + Eigen::Vector3d(dx, dy, dz) + jitter);
        d2[n] = offset[n].squaredNorm();
        d2_min = std::min(d2_min, d2[n]);
        ++n;
      }
    }
  }
  // Smooth minimum m = d2_min - ln(sum exp(-k (d2_i - d2_min))) / k, weights = softmax. Terms
  // more than kCutoff beyond the nearest weigh under exp(-32) ~ 1e-14 and are skipped.
  constexpr double kCutoff = 0.5;
  double sum = 0.0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const double excess = d2[i] - d2_min;
    if (excess > kCutoff) continue;
    const double e = std::exp(-kSharpness * excess);
    sum += e;
    weighted += e * offset[i];
  }
  const double m = d2_min - std::log(sum) / kSharpness;
  const Eigen::Vector3d dm_dq = 2.0 * weighted / sum;  // sum of w_i * grad(d_i^2)
  const double e = std::exp(-m / kWidth);
  HeightSample s;
  s.height_m = amplitude_ * (2.0 * e - 1.0);
  s.gradient = (amplitude_ * 2.0 * e * (-1.0 / kWidth) * inv_cell_) * dm_dq;
  return s;
}

bool FourierSeries::add(const Term& term) {
  if (count_ >= kMaxTerms) return false;
  terms_[count_++] = term;
  max_height_ += std::abs(term.amplitude_m);
  return true;
}

FourierSeries FourierSeries::sinusoid(double amplitude_m, double wavelength_m,
                                      const Eigen::Vector3d& direction) {
  FourierSeries f;
  f.add({amplitude_m, direction.normalized() / wavelength_m, 0.0});
  return f;
}

HeightSample FourierSeries::sample(const Eigen::Vector3d& p) const noexcept {
  HeightSample s;
  for (int j = 0; j < count_; ++j) {
    const Term& t = terms_[j];
    const double arg = kTwoPi * t.wave_vector_per_m.dot(p) + t.phase_rad;
    s.height_m += t.amplitude_m * std::sin(arg);
    s.gradient += (t.amplitude_m * kTwoPi * std::cos(arg)) * t.wave_vector_per_m;
  }
  return s;
}

}  // namespace lap::haptics
