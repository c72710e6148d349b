#include "haptics/setup/mesh_generators.h"

#include <cmath>

#include "haptics/setup/mesh_repair.h"

namespace lap::haptics {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

TriangleMesh make_mapped_sphere(int32_t stacks, int32_t slices,
                                const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& f) {
  TriangleMesh m;
  // Poles on the y axis (y up).
  m.positions.push_back(f(Eigen::Vector3d(0, 1, 0)));
  for (int32_t i = 1; i < stacks; ++i) {
    const double theta = kPi * i / stacks;
    for (int32_t j = 0; j < slices; ++j) {
      const double phi = 2.0 * kPi * j / slices;
      const Eigen::Vector3d u(std::sin(theta) * std::cos(phi), std::cos(theta),
                              -std::sin(theta) * std::sin(phi));
      m.positions.push_back(f(u));
    }
  }
  m.positions.push_back(f(Eigen::Vector3d(0, -1, 0)));
  const int32_t south = m.vertex_count() - 1;
  auto ring = [slices](int32_t i, int32_t j) { return 1 + (i - 1) * slices + (j % slices); };
  for (int32_t j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int32_t i = 1; i + 1 < stacks; ++i) {
    for (int32_t j = 0; j < slices; ++j) {
      const int32_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
      m.triangles.push_back({a, c, d});
      m.triangles.push_back({a, d, b});
    }
  }
  for (int32_t j = 0; j < slices; ++j) {
    m.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
  }
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_uv_sphere(double radius, int32_t stacks, int32_t slices) {
  return make_mapped_sphere(
      stacks, slices, [radius](const Eigen::Vector3d& u) { return Eigen::Vector3d(radius * u); });
}

TriangleMesh make_box(const Eigen::Vector3d& size, int32_t n) {
  TriangleMesh m;
  const Eigen::Vector3d h = 0.5 * size;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      // In-plane axes u, v with u x v along the outward normal.
      int u = (axis + 1) % 3;
      int v = (axis + 2) % 3;
      if (sign < 0) std::swap(u, v);
      const int32_t base = m.vertex_count();
      for (int32_t i = 0; i <= n; ++i) {
        for (int32_t j = 0; j <= n; ++j) {
          Eigen::Vector3d p;
          p[axis] = sign * h[axis];
          p[u] = (static_cast<double>(i) / n - 0.5) * size[u];
          p[v] = (static_cast<double>(j) / n - 0.5) * size[v];
          m.positions.push_back(p);
        }
      }
      for (int32_t i = 0; i < n; ++i) {
        for (int32_t j = 0; j < n; ++j) {
          const int32_t a = base + i * (n + 1) + j, b = a + (n + 1), c = a + 1, d = b + 1;
          m.triangles.push_back({a, b, d});
          m.triangles.push_back({a, d, c});
        }
      }
    }
  }
  // Faces meet at shared edge vertices, computed identically from both faces.
  weld_vertices(m, 1e-12 * size.norm());
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_cylinder(double radius, double length, int32_t slices, int32_t rings) {
  TriangleMesh m;
  for (int32_t r = 0; r <= rings; ++r) {
    const double y = length * r / rings;
    for (int32_t j = 0; j < slices; ++j) {
      const double phi = 2.0 * kPi * j / slices;
      m.positions.emplace_back(radius * std::cos(phi), y, -radius * std::sin(phi));
    }
  }
  auto at = [slices](int32_t r, int32_t j) { return r * slices + (j % slices); };
  for (int32_t r = 0; r < rings; ++r) {
    for (int32_t j = 0; j < slices; ++j) {
      const int32_t a = at(r, j), b = at(r, j + 1), c = at(r + 1, j), d = at(r + 1, j + 1);
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  }
  const int32_t bottom = m.vertex_count();
  m.positions.emplace_back(0.0, 0.0, 0.0);
  const int32_t top = m.vertex_count();
  m.positions.emplace_back(0.0, length, 0.0);
  for (int32_t j = 0; j < slices; ++j) {
    m.triangles.push_back({bottom, at(0, j + 1), at(0, j)});
    m.triangles.push_back({top, at(rings, j), at(rings, j + 1)});
  }
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_plate(double size, int32_t n) {
  TriangleMesh m;
  for (int32_t i = 0; i <= n; ++i) {
    for (int32_t j = 0; j <= n; ++j) {
      m.positions.emplace_back(size * (static_cast<double>(i) / n - 0.5), 0.0,
                               size * (static_cast<double>(j) / n - 0.5));
    }
  }
  for (int32_t i = 0; i < n; ++i) {
    for (int32_t j = 0; j < n; ++j) {
      const int32_t a = i * (n + 1) + j, b = a + (n + 1), c = a + 1, d = b + 1;
      // x along i, z along j: (z x x) = +y, so go a -> c -> d for an upward normal.
      m.triangles.push_back({a, c, d});
      m.triangles.push_back({a, d, b});
    }
  }
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_voxel_solid(int32_t nx, int32_t ny, int32_t nz, double cell,
                              const std::function<bool(int32_t, int32_t, int32_t)>& occupied) {
  auto filled = [&](int32_t i, int32_t j, int32_t k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && occupied(i, j, k);
  };
  TriangleMesh m;
  const int axes[3][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}};
  for (int32_t i = 0; i < nx; ++i) {
    for (int32_t j = 0; j < ny; ++j) {
      for (int32_t k = 0; k < nz; ++k) {
        if (!filled(i, j, k)) continue;
        const std::array<int32_t, 3> c = {i, j, k};
        for (const auto& ax : axes) {
          for (int sign = -1; sign <= 1; sign += 2) {
            std::array<int32_t, 3> nb = c;
            nb[ax[0]] += sign;
            if (filled(nb[0], nb[1], nb[2])) continue;
            // Face of the cell on side `sign` of axis ax[0], spanned by ax[1] and ax[2].
            int u = ax[1];
            int v = ax[2];
            if (sign < 0) std::swap(u, v);
            Eigen::Vector3d o(c[0], c[1], c[2]);
            if (sign > 0) o[ax[0]] += 1.0;
            Eigen::Vector3d du = Eigen::Vector3d::Zero();
            Eigen::Vector3d dv = Eigen::Vector3d::Zero();
            du[u] = 1.0;
            dv[v] = 1.0;
            const auto base = m.vertex_count();
            for (const Eigen::Vector3d& p :
                 {o, Eigen::Vector3d(o + du), Eigen::Vector3d(o + du + dv),
                  Eigen::Vector3d(o + dv)}) {
              m.positions.push_back(p * cell);
            }
            m.triangles.push_back({base, base + 1, base + 2});
            m.triangles.push_back({base, base + 2, base + 3});
          }
        }
      }
    }
  }
  weld_vertices(m, 1e-9 * cell);
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_bowl(double radius, int32_t stacks, int32_t slices) {
  // The lower half of a latitude/longitude sphere, wound so the normal points inwards.
  TriangleMesh m;
  const int32_t half = stacks / 2;
  for (int32_t i = half; i < stacks; ++i) {
    const double theta = kPi * i / stacks;
    for (int32_t j = 0; j < slices; ++j) {
      const double phi = 2.0 * kPi * j / slices;
      m.positions.emplace_back(radius * std::sin(theta) * std::cos(phi), radius * std::cos(theta),
                               -radius * std::sin(theta) * std::sin(phi));
    }
  }
  m.positions.emplace_back(0.0, -radius, 0.0);
  const int32_t bottom = m.vertex_count() - 1;
  auto ring = [slices, half](int32_t i, int32_t j) { return (i - half) * slices + (j % slices); };
  for (int32_t i = half; i + 1 < stacks; ++i) {
    for (int32_t j = 0; j < slices; ++j) {
      const int32_t a = ring(i, j), b = ring(i, j + 1), c = ring(i + 1, j), d = ring(i + 1, j + 1);
      m.triangles.push_back({a, d, c});
      m.triangles.push_back({a, b, d});
    }
  }
  for (int32_t j = 0; j < slices; ++j) {
    m.triangles.push_back({bottom, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
  }
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_stand_in_liver() {
  // An ellipsoid flattened underneath with a right-lobe bulge: about 18 x 9 x 14 cm, centred
  // above the gallbladder fossa. Gross dimensions follow adult liver anatomy.
  return make_mapped_sphere(48, 96, [](const Eigen::Vector3d& u) {
    Eigen::Vector3d p(0.09 * u.x(), 0.045 * u.y(), 0.07 * u.z());
    if (p.y() < 0.0) p.y() *= 0.55;                                 // flatter visceral face
    p.y() += 0.012 * std::exp(-std::pow((u.x() + 0.4) / 0.45, 2));  // right lobe dome
    p.z() *= 1.0 - 0.25 * std::max(0.0, u.x());                     // tapering left lobe
    return Eigen::Vector3d(p + Eigen::Vector3d(0.0, 0.06, 0.0));
  });
}

TriangleMesh make_stand_in_gallbladder() {
  // Pear-shaped sac about 8 cm long, 3 cm wide, lying under the liver, fundus forward (+z).
  return make_mapped_sphere(32, 48, [](const Eigen::Vector3d& u) {
    const double along = u.z();  // -1 neck ... +1 fundus
    const double width = 0.015 * (0.75 + 0.25 * along);
    Eigen::Vector3d p(width * u.x(), width * u.y(), 0.04 * along);
    return Eigen::Vector3d(p + Eigen::Vector3d(-0.02, 0.02, 0.03));
  });
}

TriangleMesh make_stand_in_cystic_duct() {
  // Closed tube, 2.5 mm radius (5 mm outer diameter: 3 mm inside with a 1 mm wall) and 3.5 cm
  // long, leaving the gallbladder neck medially (+x), backwards and down towards the common bile
  // duct. The cystic duct is 2–4 cm long and 2–3 mm across inside (Gray's Anatomy); the wall's
  // thickness is an estimate (docs/tissue-parameters.md). The session fits its modal shell to
  // this tube (sim/setup/duct_fit.h).
  TriangleMesh m = make_cylinder(0.0025, 0.035, 24, 14);
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(Eigen::Vector3d(-0.018, 0.018, -0.004));
  T.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(),
                                              Eigen::Vector3d(0.85, -0.3, -0.45).normalized()));
  m.transform(T);
  return m;
}

}  // namespace lap::haptics
