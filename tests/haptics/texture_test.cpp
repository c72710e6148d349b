// Haptic textures (§6.3): procedural fields against their own finite differences and bounds;
// a sinusoidal Fourier texture on a flat face against the analytic height and gradient; the
// collision-state flips of Figure 6-5; the bounded direction change of the eq. 6-4 mix; §6.6.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "haptics/friction.h"
#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/procedural_textures.h"
#include "haptics/setup/mesh_generators.h"
#include "haptics/shading_normals.h"
#include "haptics/texture_force.h"
#include "tests/test_support.h"

namespace lap::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 0.001;
constexpr double kK = 1000.0;
constexpr double kTop = 0.05;
constexpr double kA = 0.0005;      // texture amplitude [m]
constexpr double kLambda = 0.005;  // wavelength [m]

using test::angle_between;

void check_field(const HeightField& f, const char* name, double scale_m) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const HeightSample s = f.sample(p);
    Eigen::Vector3d fd;
    const double h = 1e-7 * scale_m / 0.001;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[a] = h;
      fd[a] = (f.sample(p + d).height_m - f.sample(p - d).height_m) / (2.0 * h);
    }
    worst = std::max(worst, (fd - s.gradient).norm() / (f.max_height_m() / scale_m));
  }
  std::printf("%s: worst |analytic - finite difference| gradient / (max h / scale) = %.2e\n", name,
              worst);
  EXPECT_LT(worst, 1e-4) << name;
  double largest = 0.0;
  for (int i = 0; i < 100000; ++i) {
    largest =
        std::max(largest, std::abs(f.sample(Eigen::Vector3d(u(rng), u(rng), u(rng))).height_m));
  }
  EXPECT_LE(largest, f.max_height_m()) << name;
  EXPECT_GT(largest, 0.2 * f.max_height_m()) << name;  // the bound is not absurdly loose
}

TEST(ProceduralTextures, AnalyticGradientsMatchFiniteDifferencesAndHeightsStayBounded) {
  const PerlinNoise perlin(kA, 0.002, 3);
  const FractalNoise fbm(kA, 0.004, 5, 2.0, 0.5, 3);
  const WorleyCells worley(kA, 0.003, 3);
  FourierSeries fourier;
  fourier.add({kA, Eigen::Vector3d(200.0, 0.0, 0.0), 0.3});
  fourier.add({0.5 * kA, Eigen::Vector3d(0.0, 130.0, 310.0), 1.1});
  fourier.add({0.25 * kA, Eigen::Vector3d(-420.0, 250.0, 0.0), 2.0});
  check_field(perlin, "perlin", 0.002);
  check_field(fbm, "fbm", 0.004 / 16.0);
  check_field(worley, "worley", 0.003);
  check_field(fourier, "fourier", 0.002);
}

// Perlin noise as defined, corner by corner: the sum over the cell's 8 corners c of
// fade(1 - |x - c_x|) fade(...) fade(...) times lattice_gradient(c) . (q - c), and its gradient by
// the product rule, with each corner's gradient from lattice_gradient (the hash as defined):
// noise() shares the hash lookups between corners and finds the cell by truncation; they agree to
// rounding.
TEST(ProceduralTextures, PerlinNoiseIsTheCornerSumOfItsDefinition) {
  const PerlinNoise perlin(1.0, 1.0, 7);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-40.0, 40.0);
  const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
  const auto dfade = [](double t) { return 30.0 * t * t * (t * (t - 2.0) + 1.0); };
  double worst_value = 0.0;
  double worst_gradient = 0.0;
  for (int n = 0; n < 20000; ++n) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const Eigen::Vector3d f(std::floor(q.x()), std::floor(q.y()), std::floor(q.z()));
    const Eigen::Vector3d r = q - f;
    double value = 0.0;
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner(c & 1, (c >> 1) & 1, (c >> 2) & 1);
      const Eigen::Vector3d g = perlin.lattice_gradient(static_cast<int64_t>(f.x() + corner.x()),
                                                        static_cast<int64_t>(f.y() + corner.y()),
                                                        static_cast<int64_t>(f.z() + corner.z()));
      const Eigen::Vector3d d = r - corner;
      Eigen::Vector3d wt;
      Eigen::Vector3d dwt;
      for (int a = 0; a < 3; ++a) {
        wt[a] = corner[a] != 0.0 ? fade(r[a]) : 1.0 - fade(r[a]);
        dwt[a] = corner[a] != 0.0 ? dfade(r[a]) : -dfade(r[a]);
      }
      const double weight = wt.prod();
      value += weight * g.dot(d);
      gradient += weight * g + g.dot(d) * Eigen::Vector3d(dwt.x() * wt.y() * wt.z(),
                                                          wt.x() * dwt.y() * wt.z(),
                                                          wt.x() * wt.y() * dwt.z());
    }
    Eigen::Vector3d got;
    const double n_got = perlin.noise(q, &got);
    worst_value = std::max(worst_value, std::abs(n_got - value));
    worst_gradient = std::max(worst_gradient, (got - gradient).norm());
  }
  EXPECT_LT(worst_value, 1e-12);
  EXPECT_LT(worst_gradient, 1e-11);
}

// The fractal is the gain-weighted sum of its octaves, each Perlin's noise at lacunarity^o times
// the point over the wavelength (shifted by the octave's offset), as the definition has it: with
// the sums formed in the same order it is the same to the bit, whether the octaves are evaluated
// one at a time or several at once (FractalNoise::sample, four at a time with AVX2).
TEST(ProceduralTextures, FractalNoiseIsTheSumOfItsOctavesToTheBit) {
  constexpr double kAmplitude = 0.0001;
  constexpr double kWavelength = 0.004;
  constexpr double kLacunarity = 2.0;
  constexpr double kGain = 0.5;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (const int octaves : {1, 3, 4, 5, 8}) {
    const FractalNoise fbm(kAmplitude, kWavelength, octaves, kLacunarity, kGain, 9);
    const PerlinNoise base(1.0, 1.0, 9);
    int differing = 0;
    for (int n = 0; n < 20000; ++n) {
      const Eigen::Vector3d p(u(rng), u(rng), u(rng));
      double height = 0.0;
      Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
      double amplitude = kAmplitude;
      double scale = 1.0 / kWavelength;
      for (int o = 0; o < octaves; ++o, amplitude *= kGain, scale *= kLacunarity) {
        const Eigen::Vector3d offset(17.13 * o, 31.71 * o, 7.37 * o);
        Eigen::Vector3d g;
        height += amplitude * base.noise(p * scale + offset, &g);
        gradient += (amplitude * scale) * g;
      }
      const HeightSample got = fbm.sample(p);
      if (got.height_m != height || got.gradient != gradient) ++differing;
    }
    EXPECT_EQ(differing, 0) << octaves << " octaves";
  }
}

TEST(ProceduralTextures, PerlinAndFractalAreC1AcrossLatticePlanes) {
  const PerlinNoise perlin(kA, 0.002, 5);
  const FractalNoise fbm(kA, 0.002, 3, 2.0, 0.5, 5);
  for (const HeightField* f :
       {static_cast<const HeightField*>(&perlin), static_cast<const HeightField*>(&fbm)}) {
    for (int k = -3; k <= 3; ++k) {
      // x = k wavelengths is a lattice plane of every octave (lacunarity 2).
      const Eigen::Vector3d below(k * 0.002 - 1e-12, 0.00037, -0.00113);
      const Eigen::Vector3d above(k * 0.002 + 1e-12, 0.00037, -0.00113);
      const HeightSample a = f->sample(below);
      const HeightSample b = f->sample(above);
      EXPECT_NEAR(a.height_m, b.height_m, 1e-10);  // |grad h| x 2e-12 m
      EXPECT_LT((a.gradient - b.gradient).norm(), 1e-6);
    }
  }
}

struct TexturedBlock {
  MeshDatabase mesh = MeshDatabase::build(make_box(Eigen::Vector3d(0.1, 0.1, 0.1), 4));
  FourierSeries texture;
  explicit TexturedBlock(double amplitude = kA, double wavelength = kLambda)
      : texture(FourierSeries::sinusoid(amplitude, wavelength, Eigen::Vector3d::UnitX())) {}
  [[nodiscard]] HapticObject object(double k_mix) const {
    HapticObject o;
    o.mesh = &mesh;
    o.texture = &texture;
    o.texture_k = k_mix;
    o.law.stiffness_n_per_m = kK;
    o.law.max_force_n = 1e9;
    return o;
  }
};

double h_of(double x) { return kA * std::sin(2.0 * kPi * x / kLambda); }
double slope_of(double x) { return kA * 2.0 * kPi / kLambda * std::cos(2.0 * kPi * x / kLambda); }

TEST(Texture, SinusoidForceFollowsTheAnalyticHeightAndGradient) {
  const TexturedBlock b;
  const HapticObject o = b.object(2.0);  // K h = 1 mm > d: pure bump mapping (eq. 6-4b)
  PointProxy proxy;
  const double depth = 0.0002;  // under the original face
  proxy.reset(Eigen::Vector3d(-0.01, kTop + 0.003, 0.0));
  for (int i = 1; i <= 40; ++i)
    proxy.step({&o, 1}, Eigen::Vector3d(-0.01, kTop + 0.003 - (0.003 + depth) * i / 40.0, 0), kDt);
  int touching = 0;
  int free_ticks = 0;
  for (int i = 0; i <= 2000; ++i) {
    const double x = -0.01 + 1e-5 * i;
    const PointProxyOutput out = proxy.step({&o, 1}, Eigen::Vector3d(x, kTop - depth, 0.0), kDt);
    ASSERT_EQ(out.contact_count, 1) << "the original face is still touched, tick " << i;
    const double d = h_of(x) + depth;  // height at the IHIP minus the nearest distance (-depth)
    if (d <= 0.0) {
      EXPECT_EQ(out.force_W.norm(), 0.0) << "in a trough deeper than the HIP, tick " << i;
      ++free_ticks;
      continue;
    }
    ++touching;
    EXPECT_NEAR(out.force_W.norm(), kK * d, 1e-9) << i;
    const Eigen::Vector3d m = Eigen::Vector3d(-slope_of(x), 1.0, 0.0).normalized();
    EXPECT_LT(angle_between(out.force_W, m), 1e-9) << i;
  }
  EXPECT_GT(touching, 1000);
  EXPECT_GT(free_ticks, 300);  // d <= 0 over ~37% of a wavelength at this depth
}

TEST(Texture, CollisionStateFlipsAsInFigure6_5) {
  const TexturedBlock b;
  const HapticObject o = b.object(1.5);
  // HIP_1: above the original face, under a crest: a collision with the textured surface.
  {
    PointProxy proxy;
    const double x = kLambda / 4.0;  // crest, h = +A
    proxy.reset(Eigen::Vector3d(x, kTop + 0.003, 0.0));
    int first_force_tick = -1;
    for (int i = 1; i <= 300; ++i) {
      const double y = kTop + 0.003 - 1e-5 * i;  // descending 10 um per tick
      const PointProxyOutput out = proxy.step({&o, 1}, Eigen::Vector3d(x, y, 0.0), kDt);
      if (out.force_W.norm() > 0.0 && first_force_tick < 0) {
        first_force_tick = i;
        EXPECT_EQ(out.contact_count, 0);  // the original face is not touched yet
        EXPECT_TRUE(out.texture_contact);
      }
      if (y > kTop) {
        const double d = kA - (y - kTop);
        if (d > 0.0) {
          EXPECT_NEAR(out.force_W.y(), kK * d, 1e-9) << i;
        }
      }
    }
    // The force starts the first tick the HIP is below the crest, 0.5 mm above the face.
    EXPECT_EQ(first_force_tick, static_cast<int>(std::floor((0.003 - kA) / 1e-5 + 1e-9)) + 1);
  }
  // HIP_2: below the original face, over a trough deeper than the HIP: no collision.
  {
    PointProxy proxy;
    const double x = 3.0 * kLambda / 4.0;  // trough, h = -A
    proxy.reset(Eigen::Vector3d(x, kTop + 0.001, 0.0));
    PointProxyOutput out;
    for (int i = 1; i <= 130; ++i)
      out = proxy.step({&o, 1}, Eigen::Vector3d(x, kTop + 0.001 - 1e-5 * i, 0.0), kDt);
    ASSERT_EQ(out.contact_count, 1);     // 0.3 mm under the original face
    EXPECT_EQ(out.force_W.norm(), 0.0);  // but 0.2 mm above the trough's bottom
    for (int i = 131; i <= 200; ++i)
      out = proxy.step({&o, 1}, Eigen::Vector3d(x, kTop + 0.001 - 1e-5 * i, 0.0), kDt);
    EXPECT_NEAR(out.force_W.y(), kK * (0.001 - kA), 1e-9);  // 1 mm under: 0.5 mm into texture
  }
  // A stroke 0.1 mm above the face: contact exactly where h(x) > 0.1 mm, released elsewhere.
  {
    PointProxy proxy;
    const double y = kTop + 0.0001;
    proxy.reset(Eigen::Vector3d(-0.01, y, 0.0));
    int flips = 0;
    bool was = false;
    for (int i = 0; i <= 2000; ++i) {
      const double x = -0.01 + 1.03e-5 * i;
      const PointProxyOutput out = proxy.step({&o, 1}, Eigen::Vector3d(x, y, 0.0), kDt);
      const bool expected = h_of(x) > 0.0001;
      EXPECT_EQ(out.force_W.norm() > 0.0, expected) << "x = " << x;
      EXPECT_EQ(out.contact_count, 0);
      if (i > 0 && expected != was) ++flips;
      was = expected;
    }
    EXPECT_GE(flips, 7);  // 20 mm = four wavelengths: on and off in each
  }
}

TEST(Texture, KMixBoundsTheDirectionChangePerTickAtHighPenetration) {
  const double a = 0.0002;
  const double lambda = 0.001;  // fine and sharp: 0.2 mm bumps every 1 mm
  const TexturedBlock fine(a, lambda);
  const auto stroke = [&](double k_mix, double depth) {
    const HapticObject o = fine.object(k_mix);
    PointProxy proxy;
    proxy.reset(Eigen::Vector3d(0.0, kTop + 0.001, 0.0));
    for (int i = 1; i <= 100; ++i)
      proxy.step({&o, 1}, Eigen::Vector3d(0.0, kTop + 0.001 - (0.001 + depth) * i / 100.0, 0), kDt);
    double worst = 0.0;
    Eigen::Vector3d prev = Eigen::Vector3d::Zero();
    for (int i = 1; i <= 1000; ++i) {
      const Eigen::Vector3d f =
          proxy.step({&o, 1}, Eigen::Vector3d(2e-5 * i, kTop - depth, 0.0), kDt).force_W;
      if (i > 1) worst = std::max(worst, angle_between(prev, f));
      prev = f;
    }
    return worst;
  };
  const double depth = 0.003;  // 15 texture heights
  const double k_mix = 1.0;
  const double mixed = stroke(k_mix, depth);
  const double bump = stroke(1e3, depth);  // K h >= d: the force along M alone (eq. 6-4b)
  // F = (d - Kh) N + Kh M: between ticks F changes by Kh |dM| and |F| >= d - Kh, so the turn is
  // at most Kh |dM| / (d - Kh), with |dM| <= |h''|max dx = a (2 pi / lambda)^2 dx.
  const double kh = k_mix * a;
  const double dm = a * std::pow(2.0 * kPi / lambda, 2) * 2e-5;
  const double bound = kh * dm / (depth - kh);
  std::printf("K mix: worst turn per tick %.2e rad (bound %.2e), bump mapping alone %.2e rad\n",
              mixed, bound, bump);
  EXPECT_LE(mixed, bound * 1.0001);
  EXPECT_GT(bump, 5.0 * mixed);
}

TEST(Texture, ShadingAndTextureAreNotCombined) {
  const TexturedBlock b;
  const ShadingNormals shading = ShadingNormals::build(b.mesh, 0.5);
  HapticObject both = b.object(1.5);
  both.shading = &shading;
  EXPECT_STRNE(surface_problem(both), "");
  HapticObject textured = b.object(1.5);
  EXPECT_STREQ(surface_problem(textured), "");
  // Rendered anyway, the texture wins and shading is ignored: the forces are identical.
  PointProxy p1;
  PointProxy p2;
  p1.reset(Eigen::Vector3d(0.001, kTop + 0.001, 0.0));
  p2.reset(Eigen::Vector3d(0.001, kTop + 0.001, 0.0));
  for (int i = 1; i <= 300; ++i) {
    const Eigen::Vector3d hip(0.001 + 1e-5 * i, kTop + 0.001 - 1e-5 * i, 0.0);
    EXPECT_EQ(
        (p1.step({&both, 1}, hip, kDt).force_W - p2.step({&textured, 1}, hip, kDt).force_W).norm(),
        0.0);
  }
}

TEST(Texture, FrictionTextureAndAMovingObjectWorkTogether) {
  TexturedBlock b;
  FrictionModel friction;
  friction.mu_static = 0.4;
  friction.mu_dynamic = 0.3;
  friction.stick_stiffness_n_per_m = 2000.0;
  friction.slide_stiffness_n_per_m = 1500.0;
  HapticObject o = b.object(1.5);
  o.friction = &friction;
  PointProxy proxy;
  proxy.reset(Eigen::Vector3d(0.0, kTop + 0.002, 0.0));
  for (int i = 1; i <= 40; ++i)
    proxy.step({&o, 1}, Eigen::Vector3d(0.0, kTop + 0.002 - 0.0032 * i / 40.0, 0), kDt);
  // The block moves up and sideways while the HIP strokes it the other way.
  int sliding = 0;
  double worst_ratio_error = 0.0;
  for (int i = 1; i <= 1500; ++i) {
    o.prev_pose_WO = o.pose_WO;
    o.pose_WO.translation() = Eigen::Vector3d(-5e-6 * i, 2e-7 * i, 0.0);
    const Eigen::Vector3d hip(1e-5 * i, kTop - 0.0012, 0.0);
    const PointProxyOutput out = proxy.step({&o, 1}, hip, kDt);
    ASSERT_TRUE(out.force_W.allFinite());
    ASSERT_EQ(out.contact_count, 1) << i;
    const Eigen::Vector3d normal_part = out.force_W - out.friction_W;
    // The texture tilts the normal part off the face normal (its x component follows -h').
    const double x_O = hip.x() - o.pose_WO.translation().x();
    if (std::abs(slope_of(x_O)) > 0.3) {
      EXPECT_LT(normal_part.x() * slope_of(x_O), 0.0) << i;
    }
    if (proxy.friction_state().phase == FrictionState::Phase::kSliding && i > 100) {
      ++sliding;
      const double fn = normal_part.y();
      worst_ratio_error =
          std::max(worst_ratio_error, std::abs(out.friction_W.norm() / fn - friction.mu_dynamic));
      EXPECT_LT(out.friction_W.x(), 0.0);  // resists the HIP's motion relative to the block
    }
  }
  EXPECT_GT(sliding, 1000);
  EXPECT_LT(worst_ratio_error, 0.02);
}

}  // namespace
}  // namespace lap::haptics
