#include "sim/authoring/demo_assets.h"

#include <cmath>
#include <functional>

#include "haptics/setup/mesh_generators.h"
#include "sim/authoring/expert_run.h"
#include "sim/setup/mesh_loader.h"
#include "sim/setup/png_writer.h"

namespace lap::sim {
namespace {

namespace fs = std::filesystem;

// A profile curve sampled evenly by arc length from a dense polyline of (y, radius).
std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& dense, int samples) {
  std::vector<double> length(dense.size(), 0.0);
  for (size_t i = 1; i < dense.size(); ++i) {
    length[i] = length[i - 1] + (dense[i] - dense[i - 1]).norm();
  }
  std::vector<Eigen::Vector2d> out;
  size_t j = 1;
  for (int k = 0; k <= samples; ++k) {
    const double s = length.back() * k / samples;
    while (j + 1 < dense.size() && length[j] < s) ++j;
    const double seg = length[j] - length[j - 1];
    const double f = seg > 0.0 ? (s - length[j - 1]) / seg : 0.0;
    out.push_back(dense[j - 1] + std::clamp(f, 0.0, 1.0) * (dense[j] - dense[j - 1]));
  }
  out.front().y() = 0.0;  // the poles on the axis exactly
  out.back().y() = 0.0;
  return out;
}

// The outline of a solid of revolution as r(y) on [y0, y1], r(y0) = r(y1) = 0, made dense
// for resample().
std::vector<Eigen::Vector2d> outline(double y0, double y1,
                                     const std::function<double(double)>& radius) {
  constexpr int kDense = 20000;
  std::vector<Eigen::Vector2d> d;
  for (int i = 0; i <= kDense; ++i) {
    const double y = y0 + (y1 - y0) * i / kDense;
    d.emplace_back(y, i == 0 || i == kDense ? 0.0 : std::max(radius(y), 0.0));
  }
  return d;
}

double cap(double r, double dy) { return dy * dy < r * r ? std::sqrt(r * r - dy * dy) : 0.0; }

Eigen::Vector3d v(double x, double y, double z) { return {x, y, z}; }

}  // namespace

haptics::TriangleMesh make_revolution(std::span<const Eigen::Vector2d> profile, int slices) {
  haptics::TriangleMesh m;
  const auto rings = static_cast<int32_t>(profile.size()) - 2;  // between the poles
  m.positions.emplace_back(0.0, profile.front().x(), 0.0);
  for (int32_t k = 1; k <= rings; ++k) {
    for (int j = 0; j < slices; ++j) {
      const double a = 2.0 * M_PI * j / slices;
      const Eigen::Vector2d& p = profile[static_cast<size_t>(k)];
      m.positions.emplace_back(p.y() * std::cos(a), p.x(), p.y() * std::sin(a));
    }
  }
  m.positions.emplace_back(0.0, profile.back().x(), 0.0);
  const int32_t top = static_cast<int32_t>(m.positions.size()) - 1;
  auto ring = [&](int32_t k, int j) { return 1 + (k - 1) * slices + (j % slices); };
  // Outward: (along the profile) × (around the axis); see the file's test for the check.
  for (int j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int32_t k = 1; k < rings; ++k) {
    for (int j = 0; j < slices; ++j) {
      m.triangles.push_back({ring(k, j), ring(k + 1, j), ring(k, j + 1)});
      m.triangles.push_back({ring(k + 1, j), ring(k + 1, j + 1), ring(k, j + 1)});
    }
  }
  for (int j = 0; j < slices; ++j) m.triangles.push_back({ring(rings, j), top, ring(rings, j + 1)});
  return m;
}

haptics::TriangleMesh make_dumbbell(double ball_radius_m, double half_span_m, double bar_radius_m) {
  const double r = ball_radius_m;
  const double h = half_span_m;
  const auto dense = outline(-h - r, h + r, [&](double y) {
    double rad = std::max(cap(r, y - h), cap(r, y + h));
    if (std::abs(y) <= h) rad = std::max(rad, bar_radius_m);
    return rad;
  });
  return make_revolution(resample(dense, 160), 48);
}

haptics::TriangleMesh make_rocket() {
  // [m] from the nozzle's exit (y = 0) to the nose's tip (y = 0.12): the bell narrowing to its
  // throat (concave), the shoulder, the body with a waist (concave), the ogive nose.
  const auto radius = [](double y) {
    if (y < 0.02) return 0.014 - 0.008 * std::sin(0.5 * M_PI * y / 0.02);  // bell to throat
    if (y < 0.03) return 0.006 + 0.006 * std::sin(0.5 * M_PI * (y - 0.02) / 0.01);  // shoulder
    if (y < 0.05) return 0.012;
    if (y < 0.07) return 0.012 - 0.003 * std::sin(M_PI * (y - 0.05) / 0.02);  // waist
    if (y < 0.09) return 0.012;
    return 0.012 * std::sqrt(std::max(0.0, 1.0 - std::pow((y - 0.09) / 0.03, 2)));  // nose
  };
  auto dense = outline(0.0, 0.12, radius);
  // A flat exit disc: the outline goes out from the axis at y = 0 first.
  for (int i = 1; i <= 200; ++i)
    dense.insert(dense.begin() + i, Eigen::Vector2d(0.0, 0.014 * i / 200));
  return make_revolution(resample(dense, 220), 48);
}

std::vector<std::string> demo_names() {
  return {"floating_dumbbells", "concave_rocket",    "pushed_object",
          "deformable_ball",    "textured_surfaces", "frictional_surface"};
}

Status write_demo_assets(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return diagnostic(dir.string() + ": cannot create the folder: " + ec.message());
  const std::pair<const char*, haptics::TriangleMesh> meshes[] = {
      {"dumbbell.obj", make_dumbbell(0.012, 0.025, 0.004)},
      {"rocket.obj", make_rocket()},
      {"block.obj", haptics::make_box({0.04, 0.02, 0.02}, 4)},
      {"ball.obj", haptics::make_uv_sphere(0.03, 24, 48)},
      {"slab.obj", haptics::make_box({0.06, 0.01, 0.06}, 12)},
  };
  for (const auto& [name, mesh] : meshes) {
    if (Status s = save_obj(mesh, dir / name); !s.ok()) return s;
  }
  // Figure 6-6's height map: an egg-crate of bumps, four periods across the image, mid-grey the
  // surface.
  constexpr int kSide = 64;
  std::vector<uint8_t> grey(static_cast<size_t>(kSide) * kSide);
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) {
      const double h =
          std::sin(2.0 * M_PI * 4.0 * x / kSide) * std::sin(2.0 * M_PI * 4.0 * y / kSide);
      grey[static_cast<size_t>(y) * kSide + x] =
          static_cast<uint8_t>(std::lround(127.5 + 127.0 * h));
    }
  }
  return save_grey_png(kSide, kSide, grey, dir / "bumps.png");
}

hardware::ScriptedTrajectory tip_path_script(const Scene& scene, int side,
                                             std::span<const TipWaypoint> path) {
  hardware::ScriptedTrajectory t;
  const ToolSpec* tool =
      scene.scenario.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
  const TrocarSpec* port = tool == nullptr ? nullptr : scene.scenario.trocar(tool->trocar);
  if (port == nullptr) return t;
  auto add = [&](double time_s, const Eigen::Vector3d& tip_W) {
    const Eigen::Vector3d axis = (tip_W - port->position_m).normalized();
    const double inside = (tip_W - port->position_m).norm();
    hardware::Keyframe k;
    k.time_s = time_s;
    k.position_W = port->position_m - (tool->shaft_length_m - inside) * axis;
    k.gripper_angle_rad = 0.6;
    t.keyframes.push_back(k);
  };
  // The device interpolates the handle linearly between keyframes, which through the pivot
  // bows the tip's path (a 4 cm stroke 15 cm below the port sags 0.8 mm in the middle): a
  // keyframe every millimetre of the tip's travel keeps it on the straight line within microns.
  constexpr double kStepM = 0.001;
  for (size_t i = 0; i < path.size(); ++i) {
    if (i > 0) {
      const TipWaypoint& a = path[i - 1];
      const TipWaypoint& b = path[i];
      const auto pieces = static_cast<int>(std::ceil((b.tip_W - a.tip_W).norm() / kStepM));
      for (int k = 1; k < pieces; ++k) {
        const double f = static_cast<double>(k) / pieces;
        add(a.time_s + f * (b.time_s - a.time_s), a.tip_W + f * (b.tip_W - a.tip_W));
      }
    }
    add(path[i].time_s, path[i].tip_W);
  }
  return t;
}

std::array<std::vector<TipWaypoint>, 2> demo_tip_paths(const std::string& demo) {
  // Each demo's left tool waits, parked clear of everything, unless it has work to do.
  if (demo == "floating_dumbbells") {
    // The ray lowered onto both dumbbells' front balls at once (Figure 5-15), ending level with
    // the port (6 mm below the balls' tops): a ray held by a spring at each end (the passive
    // response, haptics/segment_proxy.h) rests on two bumps near its tip only when it lies along
    // the line of their tops; tilted, it pivots on the deeper one.
    return {{{{0.0, v(-0.15, 0.07, 0.0)}, {3.0, v(-0.15, 0.07, 0.0)}},
             {{0.0, v(-0.07, 0.03, 0.025)},
              {0.5, v(-0.07, 0.03, 0.025)},
              {1.5, v(-0.07, 0.006, 0.025)},
              {3.0, v(-0.07, 0.006, 0.025)}}}};
  }
  if (demo == "concave_rocket") {
    // The ray lowered along the rocket, bridging the nozzle's bell and the body (Figure 5-17):
    // it ends on the line through the bell's rim (x = -0.06, 14 mm) and the far end of the body
    // (x = 0.03, 12 mm), which clears the throat, the near body and the waist, 2.5 mm below it
    // (as the dumbbells' ray, level with the tops it rests on).
    return {{{{0.0, v(-0.15, 0.07, 0.0)}, {3.0, v(-0.15, 0.07, 0.0)}},
             {{0.0, v(-0.075, 0.03, 0.0)},
              {0.5, v(-0.075, 0.03, 0.0)},
              {1.5, v(-0.075, 0.01183, 0.0)},
              {3.0, v(-0.075, 0.01183, 0.0)}}}};
  }
  if (demo == "pushed_object") {
    // The point probe comes in along -x, meets the block's face at x = 0.02 and pushes it 3 cm
    // through its centre (Figure 6-8), then rests.
    return {{{{0.0, v(-0.15, 0.07, 0.0)}, {3.5, v(-0.15, 0.07, 0.0)}},
             {{0.0, v(0.05, 0.0, 0.0)},
              {0.5, v(0.05, 0.0, 0.0)},
              {2.5, v(-0.01, 0.0, 0.0)},
              {3.5, v(-0.01, 0.0, 0.0)}}}};
  }
  if (demo == "deformable_ball") {
    // Pressed 1 cm into the ball from above, held, and let go (Figure 6-10).
    return {{{{0.0, v(-0.15, 0.07, 0.0)}, {4.0, v(-0.15, 0.07, 0.0)}},
             {{0.0, v(0.0, 0.05, 0.0)},
              {0.5, v(0.0, 0.05, 0.0)},
              {1.5, v(0.0, 0.02, 0.0)},
              {2.5, v(0.0, 0.02, 0.0)},
              {3.5, v(0.0, 0.05, 0.0)},
              {4.0, v(0.0, 0.05, 0.0)}}}};
  }
  // A stroke: down 2 mm into a slab's top (y = 0) at x0 - 2 cm, across 4 cm along +x, up.
  const auto stroke = [](double x0) {
    return std::vector<TipWaypoint>{{0.0, v(x0 - 0.02, 0.01, 0.0)},
                                    {0.5, v(x0 - 0.02, 0.01, 0.0)},
                                    {1.0, v(x0 - 0.02, -0.002, 0.0)},
                                    {3.0, v(x0 + 0.02, -0.002, 0.0)},
                                    {3.5, v(x0 + 0.02, 0.01, 0.0)}};
  };
  if (demo == "textured_surfaces") return {stroke(-0.04), stroke(0.04)};
  if (demo == "frictional_surface") {
    return {{{{0.0, v(-0.15, 0.07, 0.0)}, {3.5, v(-0.15, 0.07, 0.0)}}, stroke(0.0)}};
  }
  return {};
}

Status write_demo_scripts(const fs::path& scenarios_dir, const fs::path& scripts_dir) {
  for (const std::string& demo : demo_names()) {
    const fs::path file = scenarios_dir / "demos" / (demo + ".yaml");
    const SceneLoadResult scene = load_scene_file(file);
    if (!scene.ok()) return scene.diagnostics();
    const std::array<std::vector<TipWaypoint>, 2> paths = demo_tip_paths(demo);
    const fs::path out = scripts_dir / demo;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) return diagnostic(out.string() + ": cannot create the folder: " + ec.message());
    for (int side = 0; side < 2; ++side) {
      const hardware::ScriptedTrajectory t =
          tip_path_script(scene.value(), side, paths[static_cast<size_t>(side)]);
      if (t.keyframes.empty()) return diagnostic(file.string() + ": no tool path for a side");
      if (Status s = save_trajectory_csv(t, out / (side == 0 ? "demo_left.csv" : "demo_right.csv"));
          !s.ok()) {
        return s;
      }
    }
  }
  return {};
}

}  // namespace lap::sim
