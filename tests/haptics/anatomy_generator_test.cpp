#include "haptics/setup/anatomy_generator.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include "haptics/setup/mesh_validation.h"

namespace lap::haptics {
namespace {

using V3 = Eigen::Vector3d;

std::vector<GeneratedAnatomy> all_presets() {
  std::vector<GeneratedAnatomy> out;
  for (const std::string& name : anatomy_preset_names()) {
    AnatomyParameters p;
    EXPECT_TRUE(anatomy_preset(name, &p)) << name;
    out.push_back(generate_anatomy(p));
  }
  return out;
}

// Möller-Trumbore: does the segment from o to o + d (s in (0, 1)) cross triangle t?
bool segment_hits(const TriangleMesh& m, int32_t t, const V3& o, const V3& d, double* s_hit) {
  const V3& a = m.positions[m.triangles[t][0]];
  const V3 e1 = m.positions[m.triangles[t][1]] - a;
  const V3 e2 = m.positions[m.triangles[t][2]] - a;
  const V3 p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return false;
  const V3 q = o - a;
  const double u = q.dot(p) / det;
  if (u < 0.0 || u > 1.0) return false;
  const V3 r = q.cross(e1);
  const double v = d.dot(r) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  *s_hit = e2.dot(r) / det;
  return *s_hit > 0.0 && *s_hit < 1.0;
}

// Inside a closed mesh: an odd number of crossings along a long ray in a generic direction.
bool inside(const TriangleMesh& m, const V3& point) {
  const V3 d = V3(0.5772, 0.5774, 0.5771).normalized() * 10.0;
  int crossings = 0;
  for (int32_t t = 0; t < m.triangle_count(); ++t) {
    double s = 0.0;
    if (segment_hits(m, t, point, d, &s)) ++crossings;
  }
  return crossings % 2 == 1;
}

double distance_to_polyline(const std::vector<V3>& c, const V3& p, double* along = nullptr) {
  double best = 1e9;
  double acc = 0.0;
  for (size_t i = 1; i < c.size(); ++i) {
    const V3 e = c[i] - c[i - 1];
    const double f = std::clamp((p - c[i - 1]).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double d = (c[i - 1] + f * e - p).norm();
    if (d < best) {
      best = d;
      if (along != nullptr) *along = acc + f * e.norm();
    }
    acc += e.norm();
  }
  return best;
}

// Extent of the points along their principal axis and the largest extent across it.
void principal_extents(const std::vector<V3>& pts, double* length, double* width) {
  V3 mean = V3::Zero();
  for (const V3& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const V3& p : pts) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  double ext[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    double lo = 1e9, hi = -1e9;
    for (const V3& p : pts) {
      const double x = (p - mean).dot(es.eigenvectors().col(k));
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    ext[k] = hi - lo;
  }
  *length = ext[2];  // eigenvalues ascending
  *width = std::max(ext[0], ext[1]);
}

TEST(AnatomyGenerator, PresetsExistAndUnknownNamesAreRefused) {
  EXPECT_EQ(anatomy_preset_names(),
            (std::vector<std::string>{"default", "easy", "moderate", "hard"}));
  AnatomyParameters p;
  EXPECT_FALSE(anatomy_preset("impossible", &p));
  ASSERT_TRUE(anatomy_preset("hard", &p));
  EXPECT_EQ(p.name, "hard");
}

TEST(AnatomyGenerator, EveryOrganIsClosedOutwardAndTwoManifold) {
  for (const GeneratedAnatomy& a : all_presets()) {
    ASSERT_EQ(a.organs.size(), 9U);
    for (const GeneratedOrgan& o : a.organs) {
      const std::string what = a.parameters.name + "/" + o.name;
      const TriangleMesh& m = o.mesh;
      const MeshDiagnostics d = validate_mesh(m);
      EXPECT_TRUE(d.clean()) << what << ": " << (d.describe().empty() ? "" : d.describe()[0]);
      EXPECT_GT(m.signed_volume(), 0.0) << what;
      // Every edge is used by exactly two triangles, traversed once each way.
      std::map<std::pair<int32_t, int32_t>, int> directed;
      for (const Triangle& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
      }
      int bad = 0;
      for (const auto& [e, n] : directed) {
        const auto back = directed.find({e.second, e.first});
        if (n != 1 || back == directed.end() || back->second != 1) ++bad;
      }
      EXPECT_EQ(bad, 0) << what;
      ASSERT_EQ(m.normals.size(), m.positions.size()) << what;
      ASSERT_EQ(m.uvs.size(), m.positions.size()) << what;
      // Normals point out: on average away from the organ's centre (the wall: both ways).
      double outward = 0.0;
      const V3 c = m.surface_centroid();
      for (int32_t v = 0; v < m.vertex_count(); ++v) {
        EXPECT_NEAR(m.normals[v].norm(), 1.0, 1e-9) << what;
        outward += m.normals[v].dot((m.positions[v] - c).normalized());
      }
      if (o.name != "abdominal_wall" && o.name != "clips") {
        EXPECT_GT(outward, 0.0) << what;
      }
    }
  }
}

TEST(AnatomyGenerator, GallbladderSizeIsWithinTheCitedRanges) {
  for (const GeneratedAnatomy& a : all_presets()) {
    double length = 0.0;
    double width = 0.0;
    principal_extents(a.organ("gallbladder")->mesh.positions, &length, &width);
    EXPECT_GE(length, 0.07) << a.parameters.name;  // Gray's, Sabiston: 7-10 cm
    EXPECT_LE(length, 0.10) << a.parameters.name;
    EXPECT_GE(width, 0.03) << a.parameters.name;  // 3-4 cm
    EXPECT_LE(width, 0.04) << a.parameters.name;
    EXPECT_NEAR(length, a.parameters.gallbladder_length_m, 0.003) << a.parameters.name;
    std::printf("%-9s gallbladder %.1f x %.1f mm\n", a.parameters.name.c_str(), 1e3 * length,
                1e3 * width);
  }
}

TEST(AnatomyGenerator, CysticDuctMeshIsTheReportedTubeWithinTheCitedRanges) {
  for (const GeneratedAnatomy& a : all_presets()) {
    const std::string& name = a.parameters.name;
    const CysticDuctReport& r = a.cystic_duct;
    EXPECT_GE(r.length_m, 0.02) << name;  // Gray's, Sabiston: 2-4 cm
    EXPECT_LE(r.length_m, 0.04) << name;
    EXPECT_NEAR(r.length_m, a.parameters.cystic_duct_length_m, 1e-4) << name;
    // The mesh's wall lies at the outer radius from the reported centre line: measured inner
    // diameter = 2 (mean distance - wall).
    const TriangleMesh& m = a.organ("cystic_duct")->mesh;
    double sum = 0.0;
    int n = 0;
    double worst = 0.0;
    for (const V3& p : m.positions) {
      double along = 0.0;
      const double d = distance_to_polyline(r.centre_line_m, p, &along);
      if (along < 0.002 || along > r.length_m - 0.002) continue;  // the ends run on into organs
      sum += d;
      ++n;
      worst = std::max(worst, std::abs(d - 0.5 * r.outer_diameter_m));
    }
    ASSERT_GT(n, 100) << name;
    const double inner = 2.0 * (sum / n - r.wall_m);
    EXPECT_GE(inner, 0.002) << name;  // 2-4 mm inside
    EXPECT_LE(inner, 0.004) << name;
    EXPECT_NEAR(inner, a.parameters.cystic_duct_inner_diameter_m, 5e-5) << name;
    EXPECT_LT(worst, 1e-4) << name;
    EXPECT_NEAR(r.wall_m, 0.001, 1e-12) << name;
    // Cheap self-intersection check of the tube: the centre line bends nowhere tighter than the
    // tube's radius, and parts of it further apart along it than half a turn stay a diameter
    // apart.
    const std::vector<V3>& c = r.centre_line_m;
    const double radius = 0.5 * r.outer_diameter_m;
    for (size_t i = 1; i + 1 < c.size(); ++i) {
      const V3 a1 = c[i] - c[i - 1];
      const V3 b1 = c[i + 1] - c[i];
      const double turn = std::atan2(a1.cross(b1).norm(), a1.dot(b1));
      const double bend_radius = 0.5 * (a1.norm() + b1.norm()) / std::max(turn, 1e-12);
      EXPECT_GT(bend_radius, 1.5 * radius) << name << " point " << i;
    }
    for (size_t i = 0; i < c.size(); ++i) {
      for (size_t j = i + 1; j < c.size(); ++j) {
        if ((j - i) * 0.001 < 3.2 * radius) continue;  // points are about 1 mm apart
        EXPECT_GT((c[i] - c[j]).norm(), 2.0 * radius) << name << " " << i << "-" << j;
      }
    }
    std::printf("%-9s cystic duct %.1f mm long, %.2f mm inside (measured), angle %.1f deg\n",
                name.c_str(), 1e3 * r.length_m, 1e3 * inner, r.angle_to_common_hepatic_duct_deg);
  }
}

TEST(AnatomyGenerator, CommonBileDuctDiameterIsWithinTheCitedRange) {
  for (const GeneratedAnatomy& a : all_presets()) {
    const TriangleMesh& m = a.organ("common_bile_duct")->mesh;
    const V3& o = a.common_bile_duct_point_m;
    const V3& u = a.common_bile_duct_up;
    double sum = 0.0;
    int n = 0;
    double lo = 1e9;
    double hi = -1e9;
    for (const V3& p : m.positions) {
      lo = std::min(lo, (p - o).dot(u));
      hi = std::max(hi, (p - o).dot(u));
    }
    for (const V3& p : m.positions) {
      const double h = (p - o).dot(u);
      if (h < lo + 1e-4 || h > hi - 1e-4) continue;  // cap centres
      sum += ((p - o) - h * u).norm();
      ++n;
    }
    const double diameter = 2.0 * sum / n;
    EXPECT_GE(diameter, 0.006) << a.parameters.name;  // Gray's: about 6 mm; up to 8 mm normal
    EXPECT_LE(diameter, 0.008) << a.parameters.name;
    EXPECT_NEAR(diameter, a.parameters.common_bile_duct_diameter_m, 1e-4) << a.parameters.name;
    // The junction is where the parameters put it (a low insertion is a long common hepatic
    // duct), and the duct arrives at the set angle.
    EXPECT_NEAR(a.common_hepatic_duct_length_m, a.parameters.common_hepatic_duct_length_m, 1e-3)
        << a.parameters.name;
    EXPECT_NEAR(a.cystic_duct.angle_to_common_hepatic_duct_deg, a.parameters.cystic_duct_angle_deg,
                3.0)
        << a.parameters.name;
    std::printf("%-9s common bile duct %.2f mm across, common hepatic duct %.1f mm\n",
                a.parameters.name.c_str(), 1e3 * diameter, 1e3 * a.common_hepatic_duct_length_m);
  }
}

TEST(AnatomyGenerator, IncisionSiteIsOnTheDuctFacingTheCameraAndInView) {
  for (const GeneratedAnatomy& a : all_presets()) {
    const std::string& name = a.parameters.name;
    const CysticDuctReport& r = a.cystic_duct;
    const V3 camera(a.parameters.camera_x_m, a.parameters.camera_y_m, a.parameters.camera_z_m);
    const V3 to_camera = (camera - r.incision_center_m).normalized();
    EXPECT_NEAR(r.incision_normal.norm(), 1.0, 1e-12);
    EXPECT_NEAR(r.incision_normal.dot(r.incision_along), 0.0, 1e-9);
    EXPECT_GT(r.incision_normal.dot(to_camera), 0.9) << name;  // anterior wall, facing the scope
    EXPECT_NEAR(distance_to_polyline(r.centre_line_m, r.incision_center_m),
                0.5 * r.outer_diameter_m, 1e-6)
        << name;
    // Nothing lies between the laparoscope and the incision (the wall is behind the camera).
    for (const GeneratedOrgan& o : a.organs) {
      if (o.name == "abdominal_wall") continue;
      const V3 from = r.incision_center_m + 0.0005 * r.incision_normal;
      for (int32_t t = 0; t < o.mesh.triangle_count(); ++t) {
        double s = 0.0;
        EXPECT_FALSE(segment_hits(o.mesh, t, from, camera - from, &s))
            << name << ": " << o.name << " hides the incision";
      }
    }
    EXPECT_FALSE(inside(a.organ("abdominal_wall")->mesh, camera)) << name;
  }
}

TEST(AnatomyGenerator, OrgansThatMustNotOverlapDoNot) {
  for (const GeneratedAnatomy& a : all_presets()) {
    const std::string& name = a.parameters.name;
    const TriangleMesh& liver = a.organ("liver")->mesh;
    int gb_in_liver = 0;
    for (const V3& p : a.organ("gallbladder")->mesh.positions) gb_in_liver += inside(liver, p);
    EXPECT_EQ(gb_in_liver, 0) << name << ": the gallbladder lies in its fossa, not in the liver";
    int duct_in_liver = 0;
    for (const V3& p : a.cystic_duct.centre_line_m) duct_in_liver += inside(liver, p);
    EXPECT_EQ(duct_in_liver, 0) << name;
    // The cystic artery runs clear of the cystic duct (Calot's triangle has both).
    const TriangleMesh& artery = a.organ("cystic_artery")->mesh;
    double closest = 1e9;
    for (const V3& p : artery.positions) {
      closest = std::min(closest, distance_to_polyline(a.cystic_duct.centre_line_m, p));
    }
    EXPECT_GT(closest, 0.5 * a.cystic_duct.outer_diameter_m + 0.0005) << name;
    int duodenum_in_gb = 0;
    for (const V3& p : a.organ("duodenum")->mesh.positions) {
      duodenum_in_gb += inside(a.organ("gallbladder")->mesh, p);
    }
    EXPECT_EQ(duodenum_in_gb, 0) << name;
  }
}

// Every patient's: the moderate patient's two right-sided ports are placed apart from the
// others' (anatomy_parameters.h).
TEST(AnatomyGenerator, EachPortIsAHoleThroughTheAbdominalWall) {
  for (const GeneratedAnatomy& a : all_presets()) {
    const TriangleMesh& wall = a.organ("abdominal_wall")->mesh;
    ASSERT_EQ(a.ports.size(), 4U) << a.parameters.name;
    for (const PortSite& port : a.ports) {
      // The port's axis through the wall's thickness runs in no wall tissue, while a point 2 cm
      // to either side at the same depth is in the wall.
      const V3 side = port.inward.cross(V3::UnitY()).normalized();
      for (double depth : {0.005, 0.012, 0.02}) {
        const V3 q = port.position_m - depth * port.inward;
        EXPECT_FALSE(inside(wall, q)) << a.parameters.name << " " << port.name << " at " << depth;
        EXPECT_TRUE(inside(wall, q + 0.02 * side)) << a.parameters.name << " " << port.name;
        EXPECT_TRUE(inside(wall, q - 0.02 * side)) << a.parameters.name << " " << port.name;
      }
      EXPECT_LT(port.inward.z(), 0.0) << port.name;  // into the abdomen, towards the organs
    }
  }
}

TEST(AnatomyGenerator, PresetsVaryWhatTheySay) {
  std::map<std::string, GeneratedAnatomy> by_name;
  for (GeneratedAnatomy& a : all_presets()) by_name[a.parameters.name] = std::move(a);
  const auto& easy = by_name.at("easy");
  const auto& hard = by_name.at("hard");
  const auto& moderate = by_name.at("moderate");
  EXPECT_GT(easy.cystic_duct.inner_diameter_m, hard.cystic_duct.inner_diameter_m);
  EXPECT_LT(moderate.cystic_duct.length_m, by_name.at("default").cystic_duct.length_m);
  EXPECT_GT(hard.common_hepatic_duct_length_m, easy.common_hepatic_duct_length_m);  // low
  EXPECT_GT(hard.organ("hepatoduodenal_fat")->mesh.signed_volume(),
            1.5 * easy.organ("hepatoduodenal_fat")->mesh.signed_volume());
  EXPECT_GT(hard.organ("liver")->mesh.signed_volume(), easy.organ("liver")->mesh.signed_volume());
  // Tortuous: the hard duct's centre line is longer than a smooth curve between its ends would
  // need, by more than the easy one's.
  auto slack = [](const CysticDuctReport& r) {
    return r.length_m / (r.centre_line_m.back() - r.centre_line_m.front()).norm();
  };
  EXPECT_GT(slack(hard.cystic_duct), slack(easy.cystic_duct));
  // Graded: each patient harder than the one before by the duct's course, the fat and the
  // liver (docs/anatomy.md "Presets"), not by a lumen under 3 mm, which the expert's planned
  // catheter does not stay in (an open defect, docs/anatomy.md "Narrow lumens").
  EXPECT_LT(moderate.cystic_duct.length_m, easy.cystic_duct.length_m);
  EXPECT_GT(easy.parameters.cystic_duct_angle_deg, moderate.parameters.cystic_duct_angle_deg);
  EXPECT_GT(moderate.parameters.cystic_duct_angle_deg, hard.parameters.cystic_duct_angle_deg);
  EXPECT_GT(slack(hard.cystic_duct), slack(moderate.cystic_duct));
  EXPECT_GT(hard.common_hepatic_duct_length_m, moderate.common_hepatic_duct_length_m);
  for (const auto* lighter : {&easy, &moderate}) {
    const auto* heavier = lighter == &easy ? &moderate : &hard;
    EXPECT_GT(heavier->organ("hepatoduodenal_fat")->mesh.signed_volume(),
              lighter->organ("hepatoduodenal_fat")->mesh.signed_volume());
    EXPECT_GT(heavier->organ("liver")->mesh.signed_volume(),
              lighter->organ("liver")->mesh.signed_volume());
  }
  for (const auto* patient : {&easy, &moderate, &hard}) {
    EXPECT_GE(patient->cystic_duct.inner_diameter_m, 0.003 - 1e-9) << patient->parameters.name;
  }
}

TEST(AnatomyGenerator, SameParametersSameNumbers) {
  AnatomyParameters p;
  ASSERT_TRUE(anatomy_preset("hard", &p));
  const GeneratedAnatomy a = generate_anatomy(p);
  const GeneratedAnatomy b = generate_anatomy(p);
  ASSERT_EQ(a.organs.size(), b.organs.size());
  for (size_t i = 0; i < a.organs.size(); ++i) {
    EXPECT_EQ(a.organs[i].mesh.positions, b.organs[i].mesh.positions);
    EXPECT_EQ(a.organs[i].mesh.triangles, b.organs[i].mesh.triangles);
  }
}

TEST(AlbedoTexture, TilesAndIsDeterministic) {
  for (Tissue t : {Tissue::liver, Tissue::gallbladder, Tissue::fat, Tissue::bile_duct}) {
    const RgbImage a = make_albedo(t, 64);
    EXPECT_EQ(a.rgb, make_albedo(t, 64).rgb);
    ASSERT_EQ(a.rgb.size(), 64U * 64U * 3U);
  }
  // The noise wraps: opposite edges meet.
  for (double y : {0.1, 0.5, 0.9}) {
    EXPECT_NEAR(tileable_fbm(0.0, y, 4, 4, 3), tileable_fbm(1.0, y, 4, 4, 3), 1e-12);
    EXPECT_NEAR(tileable_cells(y, 0.0, 8, 3), tileable_cells(y, 1.0, 8, 3), 1e-12);
  }
  // The liver is reddish-brown, the gallbladder blue-green, fat yellow (mean colours).
  auto mean = [](const RgbImage& img) {
    V3 m = V3::Zero();
    for (size_t i = 0; i < img.rgb.size(); i += 3)
      m += V3(img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]);
    return V3(m / (img.rgb.size() / 3.0));
  };
  const V3 liver = mean(make_albedo(Tissue::liver, 64));
  EXPECT_GT(liver.x(), 2.0 * liver.y());
  const V3 gb = mean(make_albedo(Tissue::gallbladder, 64));
  EXPECT_GT(gb.y(), gb.x());
  EXPECT_GT(gb.z(), gb.x());
  const V3 fat = mean(make_albedo(Tissue::fat, 64));
  EXPECT_GT(fat.x(), 1.5 * fat.z());
  EXPECT_GT(fat.y(), 1.5 * fat.z());
}

// The liver lifted over the retracted gallbladder is folded no more than the textbook liver
// (the `default` preset's sizes with the gallbladder in its fossa, no retraction): as many
// pairs of neighbouring faces turned more than 60 degrees from each other, or fewer. The
// textbook's are in its fossa and the retracted ones' along the lifted free edge. The circular
// lift cut off at 1.5 ring radii (until stop 52) left a wall up to 4 cm high that the surface
// folded into pleats: 79-89 such pairs, turned up to 156 degrees.
TEST(AnatomyGenerator, TheLiftedLiverIsNoMoreFoldedThanTheTextbookOne) {
  const auto folds = [](const TriangleMesh& liver, double* worst_deg) {
    std::map<std::pair<int32_t, int32_t>, int32_t> first_face;
    int32_t folded = 0;
    *worst_deg = 0.0;
    for (int32_t t = 0; t < liver.triangle_count(); ++t) {
      const auto& tri = liver.triangles[static_cast<size_t>(t)];
      for (size_t e = 0; e < 3; ++e) {
        const auto [i, j] = std::minmax(tri[e], tri[(e + 1) % 3]);
        const auto [it, added] = first_face.emplace(std::pair(i, j), t);
        if (added) continue;
        const V3 n0 = liver.triangle_cross(it->second).normalized();
        const V3 n1 = liver.triangle_cross(t).normalized();
        const double deg = std::acos(std::clamp(n0.dot(n1), -1.0, 1.0)) * 180.0 / std::numbers::pi;
        *worst_deg = std::max(*worst_deg, deg);
        folded += deg > 60.0 ? 1 : 0;
      }
    }
    return folded;
  };
  AnatomyParameters in_fossa;
  ASSERT_TRUE(anatomy_preset("default", &in_fossa));
  in_fossa.gallbladder_retraction_deg = 0.0;
  double textbook_worst_deg = 0.0;
  const int32_t textbook =
      folds(generate_anatomy(in_fossa).organ("liver")->mesh, &textbook_worst_deg);
  std::printf(
      "[ anatomy ] textbook, in its fossa: %d pairs turned over 60 deg; the sharpest %.1f deg\n",
      textbook, textbook_worst_deg);
  int compared = 0;
  for (const GeneratedAnatomy& a : all_presets()) {
    ASSERT_GT(a.parameters.gallbladder_retraction_deg, 0.0) << a.parameters.name;
    double worst_deg = 0.0;
    const int32_t folded = folds(a.organ("liver")->mesh, &worst_deg);
    std::printf(
        "[ anatomy ] %s: %d pairs of the liver's neighbouring faces turned over 60 deg; the "
        "sharpest %.1f deg\n",
        a.parameters.name.c_str(), folded, worst_deg);
    EXPECT_LE(folded, textbook) << a.parameters.name;
    ++compared;
  }
  EXPECT_EQ(compared, 4);  // default, easy, moderate and hard
}

}  // namespace
}  // namespace lap::haptics
