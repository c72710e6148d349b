#include "models/shell_element.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace lap::models {
namespace {

using Mat3 = Eigen::Matrix3d;

Mat3 plane_stress(double e, double nu) {
  Mat3 d;
  d << 1.0, nu, 0.0, nu, 1.0, 0.0, 0.0, 0.0, 0.5 * (1.0 - nu);
  return d * (e / (1.0 - nu * nu));
}

// Membrane (u, v per node: 8 dofs), Q4 + incompatible modes, condensed. Rectangle a x b.
Eigen::Matrix<double, 8, 8> membrane(double a, double b, const ShellMaterial& m) {
  const Mat3 d = plane_stress(m.young_pa, m.poisson) * m.thickness_m;
  const std::array<double, 4> xi_n = {-1.0, 1.0, 1.0, -1.0};
  const std::array<double, 4> eta_n = {-1.0, -1.0, 1.0, 1.0};
  const double g = 1.0 / std::sqrt(3.0);
  Eigen::Matrix<double, 12, 12> k = Eigen::Matrix<double, 12, 12>::Zero();
  for (const double xi : {-g, g}) {
    for (const double eta : {-g, g}) {
      Eigen::Matrix<double, 3, 12> bm = Eigen::Matrix<double, 3, 12>::Zero();
      for (Eigen::Index i = 0; i < 4; ++i) {
        const double dx = 0.25 * xi_n[i] * (1.0 + eta * eta_n[i]) * (2.0 / a);
        const double dy = 0.25 * eta_n[i] * (1.0 + xi * xi_n[i]) * (2.0 / b);
        bm(0, 2 * i) = dx;
        bm(1, 2 * i + 1) = dy;
        bm(2, 2 * i) = dy;
        bm(2, 2 * i + 1) = dx;
      }
      // Incompatible modes: u += α1 (1 − ξ²) + α2 (1 − η²), v += α3 (1 − ξ²) + α4 (1 − η²).
      const double p1x = -2.0 * xi * (2.0 / a);
      const double p2y = -2.0 * eta * (2.0 / b);
      bm(0, 8) = p1x;
      bm(2, 9) = p2y;
      bm(1, 11) = p2y;
      bm(2, 10) = p1x;
      k += bm.transpose() * d * bm * (0.25 * a * b);  // weight 1 x 1, |J| = ab / 4
    }
  }
  const Eigen::Matrix<double, 8, 8> kuu = k.topLeftCorner<8, 8>();
  const Eigen::Matrix<double, 8, 4> kua = k.topRightCorner<8, 4>();
  const Eigen::Matrix<double, 4, 4> kaa = k.bottomRightCorner<4, 4>();
  return kuu - kua * kaa.ldlt().solve(kua.transpose());
}

// The 12 monomials of the ACM element and their second derivatives.
Eigen::Matrix<double, 1, 12> monomials(double x, double y) {
  Eigen::Matrix<double, 1, 12> p;
  p << 1, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y, x * x * x * y,
      x * y * y * y;
  return p;
}
Eigen::Matrix<double, 3, 12> dmonomials(double x, double y) {  // rows: w, w_x, w_y
  Eigen::Matrix<double, 3, 12> d = Eigen::Matrix<double, 3, 12>::Zero();
  d.row(0) = monomials(x, y);
  d.row(1) << 0, 1, 0, 2 * x, y, 0, 3 * x * x, 2 * x * y, y * y, 0, 3 * x * x * y, y * y * y;
  d.row(2) << 0, 0, 1, 0, x, 2 * y, 0, x * x, 2 * x * y, 3 * y * y, x * x * x, 3 * x * y * y;
  return d;
}
Eigen::Matrix<double, 3, 12> curvature_monomials(double x, double y) {  // w_xx, w_yy, 2 w_xy
  Eigen::Matrix<double, 3, 12> c = Eigen::Matrix<double, 3, 12>::Zero();
  c.row(0) << 0, 0, 0, 2, 0, 0, 6 * x, 2 * y, 0, 0, 6 * x * y, 0;
  c.row(1) << 0, 0, 0, 0, 0, 2, 0, 0, 2 * x, 6 * y, 0, 6 * x * y;
  c.row(2) << 0, 0, 0, 0, 2, 0, 0, 4 * x, 4 * y, 0, 6 * x * x, 6 * y * y;
  return c;
}

// Bending (w, θx = w_y, θy = −w_x per node: 12 dofs), ACM rectangle a x b.
Eigen::Matrix<double, 12, 12> bending(double a, double b, const ShellMaterial& m) {
  const std::array<double, 4> xs = {0.0, a, a, 0.0};
  const std::array<double, 4> ys = {0.0, 0.0, b, b};
  Eigen::Matrix<double, 12, 12> c;
  for (Eigen::Index i = 0; i < 4; ++i) {
    const Eigen::Matrix<double, 3, 12> d = dmonomials(xs[i], ys[i]);
    c.row(3 * i) = d.row(0);
    c.row(3 * i + 1) = d.row(2);
    c.row(3 * i + 2) = -d.row(1);
  }
  const Eigen::Matrix<double, 12, 12> c_inv = c.inverse();
  const double t = m.thickness_m;
  const Mat3 db = plane_stress(m.young_pa, m.poisson) * (t * t * t / 12.0);
  // 3 x 3 Gauss: exact for the degree-4 integrand.
  const std::array<double, 3> gp = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const std::array<double, 3> gw = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  Eigen::Matrix<double, 12, 12> k = Eigen::Matrix<double, 12, 12>::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double x = 0.5 * a * (1.0 + gp[i]);
      const double y = 0.5 * b * (1.0 + gp[j]);
      const Eigen::Matrix<double, 3, 12> bb = -curvature_monomials(x, y) * c_inv;
      k += bb.transpose() * db * bb * (gw[i] * gw[j] * 0.25 * a * b);
    }
  }
  return k;
}

}  // namespace

void shell_element_matrices(const std::array<Eigen::Vector3d, 4>& p, const ShellMaterial& material,
                            ShellElementMatrix* stiffness, Eigen::Matrix<double, 24, 1>* mass) {
  const Eigen::Vector3d ex = p[1] - p[0];
  const Eigen::Vector3d ey = p[3] - p[0];
  const double a = ex.norm();
  const double b = ey.norm();
  const double scale = std::max(a, b);
  if (!(a > 0.0 && b > 0.0) || std::abs(ex.dot(ey)) > 1e-6 * a * b ||
      (p[2] - (p[1] + ey)).norm() > 1e-6 * scale) {
    throw std::invalid_argument("shell element: the four nodes are not a rectangle");
  }
  Mat3 r;  // rows: local axes in global coordinates
  r.row(0) = ex / a;
  r.row(1) = ey / b;
  r.row(2) = r.row(0).cross(r.row(1));
  const Eigen::Matrix<double, 8, 8> km = membrane(a, b, material);
  const Eigen::Matrix<double, 12, 12> kb = bending(a, b, material);
  ShellElementMatrix kl = ShellElementMatrix::Zero();
  const double drill = 1e-5 * material.young_pa * material.thickness_m * a * b;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int s = 0; s < 2; ++s) {
        for (int q = 0; q < 2; ++q) kl(6 * i + s, 6 * j + q) = km(2 * i + s, 2 * j + q);
      }
      for (int s = 0; s < 3; ++s) {
        for (int q = 0; q < 3; ++q) kl(6 * i + 2 + s, 6 * j + 2 + q) = kb(3 * i + s, 3 * j + q);
      }
    }
    // Drilling: each node's θz tied softly to the element's mean θz (a rigid rotation is free).
    for (int j = 0; j < 4; ++j) kl(6 * i + 5, 6 * j + 5) += drill * ((i == j ? 1.0 : 0.0) - 0.25);
  }
  ShellElementMatrix t = ShellElementMatrix::Zero();
  for (Eigen::Index i = 0; i < 8; ++i) t.block<3, 3>(3 * i, 3 * i) = r;
  *stiffness = t.transpose() * kl * t;
  const double m = material.density_kg_per_m3 * material.thickness_m * a * b / 4.0;
  const double rot = m * material.thickness_m * material.thickness_m / 12.0;
  for (Eigen::Index i = 0; i < 4; ++i) {
    mass->segment<3>(6 * i).setConstant(m);
    mass->segment<3>(6 * i + 3).setConstant(rot);
  }
}

}  // namespace lap::models
