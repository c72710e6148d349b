// Image textures end to end (§6.3.3 a): synthetic PNG/JPEG ramps decoded, mapped by the two-stage
// method and differentiated by central differences give the expected gradient; bad height maps
// are refused with clear errors; the scenario's surface fields reach the haptic proxy.

#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <string>
#include <vector>

#include "haptics/image_height_field.h"
#include "haptics/mesh_database.h"
#include "haptics/point_proxy.h"
#include "haptics/setup/mesh_generators.h"
#include "sim/setup/height_image_loader.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/organ_surface.h"
#include "sim/setup/scene.h"
#include "tests/support/png_writer.h"
#include "tests/test_support.h"

namespace lap::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<double> ramp(int w, int h) {
  std::vector<double> v;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) v.push_back(static_cast<double>(x) / (w - 1));
  }
  return v;
}

std::string error_of(const std::filesystem::path& file) {
  const Result<haptics::HeightImage> r = load_height_image(file);
  return r.ok() ? "(no error)" : r.message();
}

// A ramp along u over one tile of 10 mm mapped on the plane z = 0: dh/dx is constant.
void expect_ramp_gradient(const haptics::HeightImage& image, double tolerance) {
  haptics::IntermediateSurface plane;
  plane.tile_u_m = 0.01;
  plane.tile_v_m = 0.01;
  const double amplitude = 0.0005;
  const haptics::ImageHeightField field(image, plane, amplitude, 0.5 * 0.01 / image.width);
  // Grey rises by 1 / (w - 1) per texel of 10 mm / w: dh/dx = 2 A w / ((w - 1) 10 mm).
  const double expected = 2.0 * amplitude * image.width / ((image.width - 1) * 0.01);
  for (double x = 0.002; x <= 0.008; x += 0.00037) {
    for (double y = 0.001; y <= 0.009; y += 0.0021) {
      const haptics::HeightSample s = field.sample(Eigen::Vector3d(x, y, 0.0));
      EXPECT_NEAR(s.gradient.x(), expected, tolerance * expected) << x << ", " << y;
      EXPECT_NEAR(s.gradient.y(), 0.0, tolerance * expected);
      EXPECT_NEAR(s.gradient.z(), 0.0, 1e-12);
      // And the height itself: mid-grey at the tile's middle texel centre line.
      const double u = x / 0.01 * image.width - 0.5;  // texel coordinate
      EXPECT_NEAR(s.height_m, amplitude * (2.0 * u / (image.width - 1) - 1.0),
                  tolerance * amplitude + 1e-12);
    }
  }
}

TEST(ImageTexture, EightBitPngRampGivesTheExpectedGradient) {
  test::TempDir dir;
  // 52 columns: grey 5 x / 255 is exact in 8 bits, so the filtered ramp is exact too
  // (Catmull-Rom reproduces linear data; central differences of a linear field are exact).
  test::write_grey_png(dir.path() / "ramp8.png", 52, 16, 8, ramp(52, 16));
  const haptics::HeightImage image = load_height_image(dir.path() / "ramp8.png").value();
  ASSERT_EQ(image.width, 52);
  ASSERT_EQ(image.height, 16);
  expect_ramp_gradient(image, 1e-5);
}

TEST(ImageTexture, SixteenBitPngRampGivesTheExpectedGradient) {
  test::TempDir dir;
  // 86 columns: 65535 / 85 = 771 levels per column, exact in 16 bits.
  test::write_grey_png(dir.path() / "ramp16.png", 86, 8, 16, ramp(86, 8));
  const haptics::HeightImage image = load_height_image(dir.path() / "ramp16.png").value();
  ASSERT_EQ(image.width, 86);
  EXPECT_FLOAT_EQ(image.at(85, 0), 1.0F);
  EXPECT_NEAR(image.at(33, 5), 33.0 / 85.0, 1e-7);
  expect_ramp_gradient(image, 1e-5);
}

TEST(ImageTexture, GreyJpegRampGivesTheExpectedGradient) {
  // tests/data/README.md: grey 5 x, one component, quality 100.
  const haptics::HeightImage image =
      load_height_image(test::source_dir() / "tests/data/ramp_grey_52x16.jpg").value();
  ASSERT_EQ(image.width, 52);
  ASSERT_EQ(image.height, 16);
  expect_ramp_gradient(image, 0.03);  // lossy coding: about a grey level of error per texel
}

TEST(ImageTexture, MappingsPutTheImageWhereExpected) {
  haptics::HeightImage image;
  image.width = 8;
  image.height = 4;
  image.values.assign(32, 0.5F);
  haptics::IntermediateSurface s;
  s.kind = haptics::IntermediateSurface::Kind::kCylinder;
  s.tile_v_m = 0.02;
  s.repeat_u = 2;
  haptics::ImageHeightField cyl(image, s, 0.001, 1e-5);
  // Radial projection: angle phi around z -> u = (phi / 2 pi + 1/2) * repeat; v = z / tile.
  const Eigen::Vector2d uv =
      cyl.map(Eigen::Vector3d(0.03 * std::cos(0.5), 0.03 * std::sin(0.5), 0.005));
  EXPECT_NEAR(uv.x(), (0.5 / (2.0 * kPi) + 0.5) * 2.0, 1e-12);
  EXPECT_NEAR(uv.y(), 0.25, 1e-12);
  s.kind = haptics::IntermediateSurface::Kind::kSphere;
  s.repeat_u = 1;
  haptics::ImageHeightField sph(image, s, 0.001, 1e-5);
  EXPECT_NEAR(sph.map(Eigen::Vector3d(0.0, 0.0, 0.04)).y(), 0.0, 1e-12);  // north pole: v = 0
  EXPECT_NEAR(sph.map(Eigen::Vector3d(0.04, 0.0, 0.0)).y(), 0.5, 1e-12);  // equator
  s.kind = haptics::IntermediateSurface::Kind::kBox;
  s.tile_u_m = 0.01;
  s.tile_v_m = 0.02;
  haptics::ImageHeightField box(image, s, 0.001, 1e-5);
  // The +x face (largest |x|) maps (y, z); the +z face maps (x, y).
  EXPECT_TRUE(box.map(Eigen::Vector3d(0.05, 0.002, 0.004)).isApprox(Eigen::Vector2d(0.2, 0.2)));
  EXPECT_TRUE(box.map(Eigen::Vector3d(0.003, 0.004, 0.05)).isApprox(Eigen::Vector2d(0.3, 0.2)));
  // A uniform image is a flat field at mid-grey: zero height and gradient everywhere.
  const haptics::HeightSample flat = box.sample(Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_NEAR(flat.height_m, 0.0, 1e-9);
  EXPECT_LT(flat.gradient.norm(), 1e-6);
}

TEST(ImageTexture, GradientMatchesDifferencesAlongTheObjectAxesForEveryMapping) {
  // eq. 6-5/6-6 along x, y, z with a tiny step is the reference for the chain-rule gradient.
  haptics::HeightImage image;
  image.width = 32;
  image.height = 32;
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) {
      image.values.push_back(static_cast<float>(0.5 + 0.4 * std::sin(0.4 * x) * std::cos(0.3 * y)));
    }
  }
  using Kind = haptics::IntermediateSurface::Kind;
  for (const Kind kind : {Kind::kPlane, Kind::kCylinder, Kind::kSphere, Kind::kBox}) {
    haptics::IntermediateSurface s;
    s.kind = kind;
    s.frame_OS = Eigen::Translation3d(0.001, -0.002, 0.003) *
                 Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized());
    s.tile_u_m = 0.02;
    s.tile_v_m = 0.03;
    s.repeat_u = 3;
    s.repeat_v = 2;
    const haptics::ImageHeightField f(image, s, 0.0005, 1e-6);
    double worst = 0.0;
    double scale = 0.0;
    for (int i = 0; i < 200; ++i) {
      // Points on a sphere of 3 cm around the surface's centre, away from the poles.
      const double phi = 0.1 + 0.031 * i;
      const double polar = 0.6 + 0.9 * std::abs(std::sin(0.17 * i));
      const Eigen::Vector3d q(0.03 * std::sin(polar) * std::cos(phi),
                              0.03 * std::sin(polar) * std::sin(phi), 0.03 * std::cos(polar));
      const Eigen::Vector3d p = s.frame_OS * q;
      Eigen::Vector3d fd;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[a] = 1e-8;
        fd[a] = (f.height(p + d) - f.height(p - d)) / 2e-8;
      }
      worst = std::max(worst, (f.sample(p).gradient - fd).norm());
      scale = std::max(scale, fd.norm());
    }
    EXPECT_LT(worst, 1e-3 * scale) << static_cast<int>(kind);
  }
}

TEST(ImageTexture, FilteredFieldIsC0AndC1AcrossTexelBoundaries) {
  haptics::HeightImage image;
  image.width = 16;
  image.height = 16;
  for (int i = 0; i < 256; ++i) image.values.push_back(static_cast<float>((i * 37 % 17) / 16.0));
  haptics::IntermediateSurface plane;
  plane.tile_u_m = 0.016;  // 1 mm texels
  plane.tile_v_m = 0.016;
  const haptics::ImageHeightField f(image, plane, 0.001, 1e-6);
  for (int k = 1; k < 15; ++k) {
    // Texel centres sit at (k + 0.5) mm: the cubic pieces join there.
    const double x = (k + 0.5) * 0.001;
    const double a = f.height(Eigen::Vector3d(x - 1e-9, 0.0073, 0.0));
    const double b = f.height(Eigen::Vector3d(x + 1e-9, 0.0073, 0.0));
    EXPECT_NEAR(a, b, 5e-9);  // |slope| <= ~2 over the 2e-9 m step
    const double slope_left = (f.height(Eigen::Vector3d(x - 1e-9, 0.0073, 0.0)) -
                               f.height(Eigen::Vector3d(x - 2e-7, 0.0073, 0.0))) /
                              (2e-7 - 1e-9);
    const double slope_right = (f.height(Eigen::Vector3d(x + 2e-7, 0.0073, 0.0)) -
                                f.height(Eigen::Vector3d(x + 1e-9, 0.0073, 0.0))) /
                               (2e-7 - 1e-9);
    EXPECT_NEAR(slope_left, slope_right, 0.002 * (std::abs(slope_left) + 1.0)) << k;
  }
}

TEST(ImageTexture, BadHeightMapsGiveClearErrors) {
  test::TempDir dir;
  const auto has = [](const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  };
  std::string e = error_of(dir.path() / "missing.png");
  EXPECT_TRUE(has(e, "missing.png") && has(e, "not found")) << e;
  dir.write("empty.png", "");
  e = error_of(dir.path() / "empty.png");
  EXPECT_TRUE(has(e, "empty.png") && has(e, "empty file")) << e;
  dir.write("text.png", "hello, not an image");
  e = error_of(dir.path() / "text.png");
  EXPECT_TRUE(has(e, "not a PNG or JPEG")) << e;
  // Wrong bit depth: a 4-bit grey PNG (valid PNG, too few height levels).
  test::write_png(dir.path() / "grey4.png", 4, 2, 4, 0, {{0x12, 0x34}, {0x56, 0x78}});
  e = error_of(dir.path() / "grey4.png");
  EXPECT_TRUE(has(e, "grey4.png") && has(e, "8- or 16-bit") && has(e, "got 4-bit")) << e;
  // Colour.
  test::write_png(dir.path() / "rgb.png", 1, 1, 8, 2, {{1, 2, 3}});
  e = error_of(dir.path() / "rgb.png");
  EXPECT_TRUE(has(e, "greyscale") && has(e, "RGB")) << e;
  // Zero size.
  test::write_png(dir.path() / "zero.png", 0, 4, 8, 0, {});
  e = error_of(dir.path() / "zero.png");
  EXPECT_TRUE(has(e, "zero size") && has(e, "0 x 4")) << e;
  // Absurd dimensions (the header alone; refused before any decoding).
  test::write_png(dir.path() / "huge.png", 100000, 100000, 16, 0, {{0, 0}});
  e = error_of(dir.path() / "huge.png");
  EXPECT_TRUE(has(e, "absurd dimensions 100000 x 100000")) << e;
  // Header promises more rows than the data holds.
  test::write_png(dir.path() / "short.png", 4, 4, 8, 0, {{1, 2, 3, 4}});
  e = error_of(dir.path() / "short.png");
  EXPECT_TRUE(has(e, "short.png") && has(e, "corrupt")) << e;
  // A colour JPEG.
  const std::vector<uint8_t> rgb(4 * 4 * 3, 128);
  const std::string jpg = (dir.path() / "colour.jpg").string();
  ASSERT_NE(stbi_write_jpg(jpg.c_str(), 4, 4, 3, rgb.data(), 90), 0);
  e = error_of(jpg);
  EXPECT_TRUE(has(e, "colour.jpg") && has(e, "greyscale JPEG") && has(e, "3 colour")) << e;
}

const char* kBoxScenario = R"(version: 1
name: textured box
organs:
  - name: box
    mesh: box.obj
    transform: {translation_m: [0.0, 0.1, 0.0]}
    material:
      stiffness_n_per_m: 1000
      friction_static: 0.4
      friction_dynamic: 0.2
      friction_map: {kind: periodic, period_m: 0.004, amplitude: 0.5}
      texture:
        kind: %KIND%
)";

std::filesystem::path write_box_scenario(test::TempDir& dir, const std::string& texture) {
  EXPECT_TRUE(
      save_obj(haptics::make_box(Eigen::Vector3d(0.04, 0.04, 0.04), 4), dir.path() / "box.obj")
          .ok());
  std::string text = kBoxScenario;
  text.replace(text.find("%KIND%"), 6, texture);
  return dir.write("s.yaml", text);
}

TEST(SurfaceProperties, ScenarioImageTextureAndFrictionReachTheProxy) {
  test::TempDir dir;
  test::write_grey_png(dir.path() / "ramp.png", 64, 64, 16, ramp(64, 64));
  const auto file = write_box_scenario(dir,
                                       "image\n"
                                       "        image: ramp.png\n"
                                       "        amplitude_m: 0.0002\n"
                                       "        k_mix: 1.0\n"
                                       "        mapping: {kind: plane, axis: [0, 1, 0], "
                                       "origin_m: [-0.005, 0, 0], tile_m: [0.01, 0.01]}");
  const SceneLoadResult r = load_scene_file(file);
  for (const auto& p : r.diagnostics()) ADD_FAILURE() << p.to_string();
  ASSERT_EQ(r.value().organs.size(), 1U);
  const Organ& organ = r.value().organs[0];
  ASSERT_TRUE(organ.height_image);
  const haptics::MeshDatabase db = haptics::MeshDatabase::build(organ.mesh);
  const OrganSurface surface = build_organ_surface(organ, db);
  ASSERT_TRUE(surface.texture && surface.friction);
  EXPECT_FALSE(surface.shading);
  EXPECT_DOUBLE_EQ(surface.friction->slide_stiffness_n_per_m, 1000.0 * 0.2 / 0.4);
  haptics::HapticObject o;
  o.mesh = &db;
  surface.apply(organ.material, &o);
  EXPECT_STREQ(haptics::surface_problem(o), "");
  // The box's top is y = 0.12. The plane's axis [0, 1, 0] is the mapping's z; the ramp rises
  // along the mapping's u. Pressing 0.1 mm into the top at two places 2 mm apart along the
  // ramp's direction: the force tilts against the rising height.
  const haptics::HeightSample s = surface.texture->sample(Eigen::Vector3d(0.0, 0.12, 0.0));
  ASSERT_GT(s.gradient.norm(), 0.01);
  EXPECT_NEAR(s.gradient.y(), 0.0, 1e-9);  // the ramp lies in the face's plane
  haptics::PointProxy proxy;
  proxy.reset(Eigen::Vector3d(0.0, 0.123, 0.0));
  haptics::PointProxyOutput out;
  for (int i = 1; i <= 40; ++i) {
    out = proxy.step({&o, 1}, Eigen::Vector3d(0.0, 0.123 - 0.0031 * i / 40.0, 0.0), 0.001);
  }
  ASSERT_EQ(out.contact_count, 1);
  const Eigen::Vector3d tangential(out.force_W.x(), 0.0, out.force_W.z());
  EXPECT_LT(tangential.dot(s.gradient), 0.0);  // M = N - grad h (eq. 6-2)
}

TEST(SurfaceProperties, ScenarioProceduralTexturesBuild) {
  for (const char* function : {"perlin", "fbm", "worley", "fourier"}) {
    test::TempDir dir;
    const auto file =
        write_box_scenario(dir, std::string("procedural\n        function: ") + function +
                                    "\n        amplitude_m: 0.0003\n"
                                    "        wavelength_m: 0.003");
    const SceneLoadResult r = load_scene_file(file);
    for (const auto& p : r.diagnostics()) ADD_FAILURE() << p.to_string();
    ASSERT_EQ(r.value().organs.size(), 1U);
    const haptics::MeshDatabase db = haptics::MeshDatabase::build(r.value().organs[0].mesh);
    const OrganSurface surface = build_organ_surface(r.value().organs[0], db);
    ASSERT_TRUE(surface.texture) << function;
    EXPECT_GT(surface.texture->max_height_m(), 0.0003 * 0.99) << function;
  }
}

TEST(SurfaceProperties, IntroductoryScenarioSurfacesBuild) {
  const SceneLoadResult r = load_scene_file(test::source_dir() / "scenarios/introductory.yaml");
  ASSERT_TRUE(r.ok());
  int shaded = 0;
  int textured = 0;
  for (const Organ& organ : r.value().organs) {
    const haptics::MeshDatabase db = haptics::MeshDatabase::build(organ.mesh);
    const OrganSurface s = build_organ_surface(organ, db);
    haptics::HapticObject o;
    o.mesh = &db;
    s.apply(organ.material, &o);
    EXPECT_STREQ(haptics::surface_problem(o), "") << organ.name;
    EXPECT_TRUE(s.friction) << organ.name;
    shaded += s.shading ? 1 : 0;
    textured += s.texture ? 1 : 0;
  }
  EXPECT_EQ(shaded, 1);    // the liver
  EXPECT_EQ(textured, 1);  // the gallbladder
}

TEST(SurfaceProperties, BadSurfaceFieldsAreReportedWithFileLineAndField) {
  test::TempDir dir;
  const auto problems = [&](const std::string& texture) {
    const auto file = write_box_scenario(dir, texture);
    std::string all;
    for (const auto& p : load_scene_file(file).diagnostics()) all += p.to_string() + "\n";
    return all;
  };
  // A texture image that is not a usable height map: named through the scenario field.
  test::write_png(dir.path() / "rgb.png", 1, 1, 8, 2, {{1, 2, 3}});
  std::string all = problems("image\n        image: rgb.png\n        amplitude_m: 0.0002");
  EXPECT_NE(all.find("organs[0].material.texture.image"), std::string::npos) << all;
  EXPECT_NE(all.find("rgb.png"), std::string::npos) << all;
  EXPECT_NE(all.find("greyscale"), std::string::npos) << all;
  all = problems(
      "image\n        image: rgb.png\n        amplitude_m: 0.0002\n        mapping: {kind: cone}");
  EXPECT_NE(all.find("expected plane, cylinder, sphere or box, got 'cone'"), std::string::npos)
      << all;
  // §6.6: shading with a texture.
  ASSERT_TRUE(
      save_obj(haptics::make_box(Eigen::Vector3d(0.04, 0.04, 0.04), 4), dir.path() / "box.obj")
          .ok());
  const auto file = dir.write("both.yaml", R"(version: 1
name: both
organs:
  - name: box
    mesh: box.obj
    material:
      stiffness_n_per_m: 1000
      shading: {enabled: true}
      texture: {kind: procedural, function: perlin, amplitude_m: 0.0001, wavelength_m: 0.002}
)");
  all.clear();
  for (const auto& p : load_scene_file(file).diagnostics()) all += p.to_string() + "\n";
  EXPECT_NE(all.find("both.yaml:8"), std::string::npos) << all;
  EXPECT_NE(all.find("organs[0].material.shading"), std::string::npos) << all;
  EXPECT_NE(all.find("6.6"), std::string::npos) << all;
  // Friction map and stiffness checks.
  const auto bad = dir.write("bad.yaml", R"(version: 1
name: bad
organs:
  - name: box
    mesh: box.obj
    material:
      stiffness_n_per_m: 1000
      friction_static: 0.3
      friction_dynamic: 0.2
      friction_stick_stiffness_n_per_m: 500
      friction_slide_stiffness_n_per_m: 800
      friction_map: {kind: sandpaper}
)");
  all.clear();
  for (const auto& p : load_scene_file(bad).diagnostics()) all += p.to_string() + "\n";
  EXPECT_NE(all.find("friction_slide_stiffness_n_per_m"), std::string::npos) << all;
  EXPECT_NE(all.find("expected uniform, periodic or random, got 'sandpaper'"), std::string::npos)
      << all;
}

}  // namespace
}  // namespace lap::sim
