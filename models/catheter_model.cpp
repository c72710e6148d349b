#include "models/catheter_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>

namespace lap::models {
namespace {

constexpr int kHalfBand = 8;
constexpr double kEnergyFloorJ = 1e-16;  // scalar half-bandwidth: particles meet ±2 neighbours
constexpr int kBandWidth = kHalfBand + 1;

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

// Adds block b at (particle p, particle q), p >= q, into the lower band.
void add_block(std::vector<double>* band, int p, int q, const Mat3& b) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int row = 3 * p + r;
      const int col = 3 * q + c;
      if (row < col) continue;  // the upper part of a diagonal block
      (*band)[static_cast<size_t>(row) * kBandWidth + (row - col)] += b(r, c);
    }
  }
}

// In-place banded Cholesky (A = L Lᵀ) and solve; false if not positive definite.
bool band_cholesky_solve(std::vector<double>* band, std::vector<double>* x, int n) {
  double* a = band->data();
  auto at = [&](int row, int col) -> double& {
    return a[static_cast<size_t>(row) * kBandWidth + (row - col)];
  };
  for (int j = 0; j < n; ++j) {
    double d = at(j, j);
    const int k0 = std::max(0, j - kHalfBand);
    for (int k = k0; k < j; ++k) d -= at(j, k) * at(j, k);
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    at(j, j) = ljj;
    const int i1 = std::min(n - 1, j + kHalfBand);
    for (int i = j + 1; i <= i1; ++i) {
      double s = at(i, j);
      const int kk = std::max(k0, i - kHalfBand);
      for (int k = kk; k < j; ++k) s -= at(i, k) * at(j, k);
      at(i, j) = s / ljj;
    }
  }
  double* y = x->data();
  for (int i = 0; i < n; ++i) {
    double s = y[i];
    for (int k = std::max(0, i - kHalfBand); k < i; ++k) s -= at(i, k) * y[k];
    y[i] = s / at(i, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k <= std::min(n - 1, i + kHalfBand); ++k) s -= at(k, i) * y[k];
    y[i] = s / at(i, i);
  }
  return true;
}

// Bending residual r = t1 − t2 at interior particle i and its Jacobian blocks with respect to
// particles i − 1, i, i + 1.
struct BendTerm {
  Vec3 r;
  Mat3 j0;
  Mat3 j1;
  Mat3 j2;
};
BendTerm bend_term(const Vec3& x0, const Vec3& x1, const Vec3& x2) {
  const Vec3 e1 = x1 - x0;
  const Vec3 e2 = x2 - x1;
  const double l1 = e1.norm();
  const double l2 = e2.norm();
  const Vec3 t1 = e1 / l1;
  const Vec3 t2 = e2 / l2;
  const Mat3 p1 = (Mat3::Identity() - t1 * t1.transpose()) / l1;  // d t1 / d e1
  const Mat3 p2 = (Mat3::Identity() - t2 * t2.transpose()) / l2;  // d t2 / d e2
  BendTerm b;
  b.r = t1 - t2;
  b.j0 = -p1;
  b.j1 = p1 + p2;
  b.j2 = -p2;
  return b;
}

// The particles a centre-line point (segment, t) moves with, and their weights; a weight of zero
// (a point on a particle) is left out, so that a link's span is what it really couples.
struct PointWeights {
  std::array<int, 2> particle{};
  std::array<double, 2> weight{};
  int count = 0;
};
PointWeights point_weights(int32_t segment, double t) {
  PointWeights w;
  if (1.0 - t != 0.0) {
    w.particle[w.count] = segment;
    w.weight[w.count++] = 1.0 - t;
  }
  if (t != 0.0) {
    w.particle[w.count] = segment + 1;
    w.weight[w.count++] = t;
  }
  return w;
}

// A link's difference x_b − x_a as Σ c_p x_p over at most four particles (merged where a and b
// share one), in particle order.
struct LinkWeights {
  std::array<int, 4> particle{};
  std::array<double, 4> coeff{};
  int count = 0;
  void add(int p, double c) {
    for (int k = 0; k < count; ++k) {
      if (particle[k] == p) {
        coeff[k] += c;
        return;
      }
    }
    int k = count++;
    while (k > 0 && particle[k - 1] > p) {
      particle[k] = particle[k - 1];
      coeff[k] = coeff[k - 1];
      --k;
    }
    particle[k] = p;
    coeff[k] = c;
  }
};
LinkWeights link_weights(const CenterlineLink& link) {
  LinkWeights lw;
  const PointWeights a = point_weights(link.segment_a, link.t_a);
  const PointWeights b = point_weights(link.segment_b, link.t_b);
  for (int k = 0; k < a.count; ++k) lw.add(a.particle[k], -a.weight[k]);
  for (int k = 0; k < b.count; ++k) lw.add(b.particle[k], b.weight[k]);
  return lw;
}

Vec3 link_difference(const LinkWeights& lw, const std::vector<Vec3>& x) {
  Vec3 d = Vec3::Zero();
  for (int k = 0; k < lw.count; ++k) d += lw.coeff[k] * x[static_cast<size_t>(lw.particle[k])];
  return d;
}

}  // namespace

CatheterModel CatheterModel::build(const CatheterSettings& s) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("catheter: " + what); };
  if (s.particles < 3 || s.particles > 4096) bad("particles must be 3..4096");
  if (!(s.length_m > 0.0)) bad("length_m must be positive");
  if (!(s.outer_diameter_m > 0.0)) bad("outer_diameter_m must be positive");
  if (!(s.bending_stiffness_n_m2 > 0.0)) bad("bending_stiffness_n_m2 must be positive");
  if (!(s.linear_density_kg_per_m > 0.0)) bad("linear_density_kg_per_m must be positive");
  if (!(s.stretch_stiffness_n_per_m >= 0.0)) bad("stretch_stiffness_n_per_m must be >= 0");
  if (!(s.drag_n_s_per_m >= 0.0) || !(s.stretch_damping_n_s_per_m >= 0.0)) {
    bad("damping must be >= 0");
  }
  if (!s.gravity_m_per_s2.allFinite()) bad("gravity must be finite");
  CatheterModel m;
  m.settings_ = s;
  m.l0_ = s.length_m / (s.particles - 1);
  m.mass_ = s.linear_density_kg_per_m * m.l0_;
  m.k_l_ = s.stretch_stiffness_n_per_m > 0.0 ? s.stretch_stiffness_n_per_m : 200.0 / m.l0_;
  m.k_b_ = s.bending_stiffness_n_m2 / m.l0_;
  return m;
}

double CatheterModel::mass_of(int32_t i) const {
  return (i == 0 || i == settings_.particles - 1) ? 0.5 * mass_ : mass_;
}

CatheterState::CatheterState(const CatheterModel& model, const Eigen::Vector3d& start,
                             const Eigen::Vector3d& direction) {
  const auto n = static_cast<size_t>(model.particle_count());
  positions.resize(n);
  velocities.assign(n, Eigen::Vector3d::Zero());
  external_force.assign(n, Eigen::Vector3d::Zero());
  fixed.assign(n, 0);
  contact_normal.assign(n, Eigen::Vector3d::UnitZ());
  contact_offset.assign(n, 0.0);
  contact_stiffness.assign(n, 0.0);
  contact_damping.assign(n, 0.0);
  contact_friction.assign(n, 0.0);
  contact_surface_velocity.assign(n, Eigen::Vector3d::Zero());
  contact_friction_damping.assign(n, 0.0);
  const Eigen::Vector3d d = direction.normalized();
  for (size_t i = 0; i < n; ++i) {
    positions[i] = start + static_cast<double>(i) * model.rest_length_m() * d;
  }
  band.assign(3 * n * kBandWidth, 0.0);
  rhs.assign(3 * n, 0.0);
  saved_positions.resize(n * kGuardDepth);
  saved_velocities.resize(n * kGuardDepth);
}

double catheter_energy(const CatheterModel& model, const CatheterState& state) {
  const int n = model.particle_count();
  double e = 0.0;
  for (int i = 0; i < n; ++i) e += 0.5 * model.mass_of(i) * state.velocities[i].squaredNorm();
  for (int i = 0; i + 1 < n; ++i) {
    const double dl = (state.positions[i + 1] - state.positions[i]).norm() - model.rest_length_m();
    e += 0.5 * model.stretch_stiffness() * dl * dl;
  }
  for (int32_t a = 0; a < state.anchor_count; ++a) {
    const CenterlineAnchor& an = state.anchors[static_cast<size_t>(a)];
    const Vec3 d = an.target_W - centerline_point(model, state.positions, an.segment, an.t);
    e += 0.5 * an.stiffness_n_per_m * d.squaredNorm();
  }
  for (int32_t l = 0; l < state.link_count; ++l) {
    const CenterlineLink& link = state.links[static_cast<size_t>(l)];
    const Vec3 d = link_difference(link_weights(link), state.positions) - link.rest_W;
    e += 0.5 * link.stiffness_n_per_m * d.squaredNorm();
  }
  for (int i = 0; i < n; ++i) {
    // A contact is linearised as a two-sided spring over a step; its energy likewise.
    const double gap = state.contact_offset[i] - state.contact_normal[i].dot(state.positions[i]);
    e += 0.5 * state.contact_stiffness[i] * gap * gap;
  }
  for (int i = 1; i + 1 < n; ++i) {
    const Vec3 t1 = (state.positions[i] - state.positions[i - 1]).normalized();
    const Vec3 t2 = (state.positions[i + 1] - state.positions[i]).normalized();
    e += 0.5 * model.bending_stiffness() * (t1 - t2).squaredNorm();
  }
  return e;
}

Eigen::Vector3d centerline_point(const CatheterModel& model,
                                 const std::vector<Eigen::Vector3d>& positions, int32_t segment,
                                 double t) {
  const int32_t last = std::min(model.particle_count(), static_cast<int32_t>(positions.size())) - 2;
  const auto i = static_cast<size_t>(std::clamp(segment, 0, std::max(last, 0)));
  const double u = std::clamp(t, 0.0, 1.0);
  return (1.0 - u) * positions[i] + u * positions[i + 1];
}

bool add_anchor(const CatheterModel& model, const CenterlineAnchor& anchor,
                CatheterState* state) noexcept {
  const bool on_catheter = anchor.segment >= 0 && anchor.segment + 1 < model.particle_count() &&
                           anchor.t >= 0.0 && anchor.t <= 1.0;
  if (!on_catheter || state->anchor_count >= CatheterState::kMaxAnchors) return false;
  state->anchors[static_cast<size_t>(state->anchor_count++)] = anchor;
  return true;
}

int32_t add_anchor_friction(const Eigen::Vector3d& axis_W, double limit_n, int32_t first_anchor,
                            CatheterState* state) noexcept {
  const int32_t count = state->anchor_count - first_anchor;
  if (state->friction_count >= CatheterState::kMaxFrictions || first_anchor < 0 || count <= 0 ||
      !axis_W.allFinite() || !(std::abs(axis_W.norm() - 1.0) < 1e-6) || !(limit_n >= 0.0)) {
    return -1;
  }
  const int32_t slot = state->friction_count++;
  state->frictions[static_cast<size_t>(slot)] = {axis_W, limit_n, first_anchor, count};
  return slot;
}

bool add_link(const CatheterModel& model, const CenterlineLink& link,
              CatheterState* state) noexcept {
  auto on_catheter = [&](int32_t segment, double t) {
    return segment >= 0 && segment + 1 < model.particle_count() && t >= 0.0 && t <= 1.0;
  };
  if (!on_catheter(link.segment_a, link.t_a) || !on_catheter(link.segment_b, link.t_b) ||
      state->link_count >= CatheterState::kMaxLinks || !link.rest_W.allFinite() ||
      !link.rest_velocity_W.allFinite() || !(link.stiffness_n_per_m >= 0.0) ||
      !(link.damping_n_s_per_m >= 0.0)) {
    return false;
  }
  const LinkWeights lw = link_weights(link);
  if (lw.count == 0 || lw.particle[lw.count - 1] - lw.particle[0] > 2) return false;  // the band
  state->links[static_cast<size_t>(state->link_count++)] = link;
  return true;
}

void clear_anchors(CatheterState* state) noexcept {
  state->anchor_count = 0;
  state->link_count = 0;
  state->friction_count = 0;
}

double catheter_gravity_energy(const CatheterModel& model, const CatheterState& state) {
  double e = 0.0;
  for (int i = 0; i < model.particle_count(); ++i) {
    e -= model.mass_of(i) * model.settings().gravity_m_per_s2.dot(state.positions[i]);
  }
  return e;
}

namespace {

void add_rhs(CatheterState* state, int i, const Vec3& f) noexcept {
  for (int c = 0; c < 3; ++c) state->rhs[3 * i + c] += f(c);
}

// Coulomb friction along particle i's contact plane, regularised (CatheterSettings::
// contact_stick_speed_m_per_s): f = −c_t P (v − v_s) with P = I − n nᵀ, v_s the surface's
// velocity and c_t = μ N / max(|P (v − v_s)|, v_stick) from the slip at the step's start, so
// at a steady slip it is μ N. Implicit in v: adds −c_t P (v − v_s) to the right-hand side and
// returns c_t P, the damping D's block (as the drag's). c_t is kept for the reaction.
Mat3 contact_friction_terms(const CatheterModel& model, CatheterState* state, int i,
                            double normal_force_n) noexcept {
  const double mu = state->contact_friction[i];
  if (!(mu > 0.0) || !(normal_force_n > 0.0)) return Mat3::Zero();
  const Vec3& nc = state->contact_normal[i];
  const Mat3 along = Mat3::Identity() - nc * nc.transpose();
  const Vec3 slip = along * (state->velocities[i] - state->contact_surface_velocity[i]);
  const double ct =
      mu * normal_force_n / std::max(slip.norm(), model.settings().contact_stick_speed_m_per_s);
  state->contact_friction_damping[i] = ct;
  add_rhs(state, i, -ct * slip);
  return ct * along;
}

// Each particle's own terms: mass, gravity, drag and its contact with a surface, into its
// diagonal block and the right-hand side f − dt K v.
void assemble_particle_terms(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const int n = model.particle_count();
  const auto& x = state->positions;
  const auto& v = state->velocities;
  for (int i = 0; i < n; ++i) {
    const Vec3 f = state->external_force[i] + model.mass_of(i) * model.settings().gravity_m_per_s2 -
                   model.settings().drag_n_s_per_m * v[i];
    for (int c = 0; c < 3; ++c) state->rhs[3 * i + c] = f(c);
    const double diag = model.mass_of(i) + dt * model.settings().drag_n_s_per_m;
    Mat3 block = diag * Mat3::Identity();
    state->contact_friction_damping[i] = 0.0;
    const double kc = state->contact_stiffness[i];
    if (kc > 0.0) {
      // Along the normal only: f = (k_c (offset − n·x) − c_c n·v) n; K = k_c n nᵀ, D = c_c n nᵀ.
      const Vec3& nc = state->contact_normal[i];
      const double depth = state->contact_offset[i] - nc.dot(x[i]);
      const Vec3 fc =
          (kc * depth - state->contact_damping[i] * nc.dot(v[i]) - dt * kc * nc.dot(v[i])) * nc;
      for (int c = 0; c < 3; ++c) state->rhs[3 * i + c] += fc(c);
      block += (dt * dt * kc + dt * state->contact_damping[i]) * nc * nc.transpose();
      // Friction on the normal force at the step's start (a surface pushes, never pulls).
      const double normal_n = kc * depth - state->contact_damping[i] * nc.dot(v[i]);
      block += dt * contact_friction_terms(model, state, i, normal_n);
    }
    add_block(&state->band, i, i, block);
  }
}

// The friction group an anchor belongs to (-1: none).
int32_t friction_of(const CatheterState& state, int32_t anchor) {
  for (int32_t g = 0; g < state.friction_count; ++g) {
    const AnchorFriction& f = state.frictions[static_cast<size_t>(g)];
    if (anchor >= f.first_anchor && anchor < f.first_anchor + f.anchor_count) return g;
  }
  return -1;
}

// Anchors on the centre line: x_a = (1 − t) x_i + t x_{i+1} = wᵀ x with w = (1 − t, t);
// f = P (k (target − x_a) + c (v_target − v_a)) acts on the two particles by w, with
// P = I − a aᵀ across the axis a of a slipping friction group (else I); K = k w wᵀ ⊗ P,
// D = c w wᵀ ⊗ P. A slipping group's anchors also carry their share of its limit, against the
// direction it slipped.
void assemble_anchors(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const auto& x = state->positions;
  const auto& v = state->velocities;
  for (int32_t a = 0; a < state->anchor_count; ++a) {
    const CenterlineAnchor& an = state->anchors[static_cast<size_t>(a)];
    const int i = an.segment;
    if (i < 0 || i + 1 >= model.particle_count()) continue;
    const int32_t g = friction_of(*state, a);
    const bool slips = g >= 0 && state->slipping[static_cast<size_t>(g)];
    Mat3 across = Mat3::Identity();
    Vec3 friction = Vec3::Zero();
    if (slips) {
      const AnchorFriction& fr = state->frictions[static_cast<size_t>(g)];
      across -= fr.axis_W * fr.axis_W.transpose();
      const double sign =
          state->friction_results[static_cast<size_t>(g)].axial_force_n > 0.0 ? 1.0 : -1.0;
      friction = sign * fr.limit_n / fr.anchor_count * fr.axis_W;
    }
    const std::array<double, 2> w = {1.0 - an.t, an.t};
    const Vec3 xa = w[0] * x[i] + w[1] * x[i + 1];
    const Vec3 va = w[0] * v[i] + w[1] * v[i + 1];
    const double k = an.stiffness_n_per_m;
    const double c = an.damping_n_s_per_m;
    const Vec3 f =
        across * (k * (an.target_W - xa) + c * (an.target_velocity_W - va) - dt * k * va) +
        friction;
    add_rhs(state, i, w[0] * f);
    add_rhs(state, i + 1, w[1] * f);
    const Mat3 s = (dt * dt * k + dt * c) * across;
    add_block(&state->band, i, i, w[0] * w[0] * s);
    add_block(&state->band, i + 1, i + 1, w[1] * w[1] * s);
    add_block(&state->band, i + 1, i, w[0] * w[1] * s);
  }
}

// Links between centre-line points: d = x_b − x_a = Σ c_p x_p (link_weights), E = ½ k |d − r|²,
// damper c (ṙ − ḋ): the force F = k (r − d) + c (ṙ − ḋ) acts on particle p by c_p; K = k c cᵀ,
// D = c c cᵀ (⊗ I). Its particles lie within ±2 of each other (add_link), inside the band.
void assemble_links(CatheterState* state, double dt) noexcept {
  const auto& x = state->positions;
  const auto& v = state->velocities;
  for (int32_t l = 0; l < state->link_count; ++l) {
    const CenterlineLink& link = state->links[static_cast<size_t>(l)];
    const LinkWeights lw = link_weights(link);
    const double k = link.stiffness_n_per_m;
    const double c = link.damping_n_s_per_m;
    const Vec3 d = link_difference(lw, x);
    const Vec3 dv = link_difference(lw, v);
    const Vec3 f = k * (link.rest_W - d) + c * (link.rest_velocity_W - dv) - dt * k * dv;
    const double s = dt * dt * k + dt * c;
    for (int p = 0; p < lw.count; ++p) {
      add_rhs(state, lw.particle[p], lw.coeff[p] * f);
      for (int q = 0; q <= p; ++q) {
        add_block(&state->band, lw.particle[p], lw.particle[q],
                  (s * lw.coeff[p] * lw.coeff[q]) * Mat3::Identity());
      }
    }
  }
}

// Each friction group's axial force on the catheter for velocities v + Δv (Δv in rhs) and the
// positions they lead to, after a solve that held it sticking.
double sticking_axial_force(const CatheterModel& model, const CatheterState& state, int32_t g,
                            double dt) {
  const AnchorFriction& fr = state.frictions[static_cast<size_t>(g)];
  double f = 0.0;
  for (int32_t a = fr.first_anchor; a < fr.first_anchor + fr.anchor_count; ++a) {
    const CenterlineAnchor& an = state.anchors[static_cast<size_t>(a)];
    const int i = an.segment;
    if (i < 0 || i + 1 >= model.particle_count()) continue;
    auto v_new = [&](int p) {
      return Vec3(state.velocities[p] +
                  Eigen::Map<const Vec3>(state.rhs.data() + static_cast<ptrdiff_t>(3) * p));
    };
    const Vec3 va = (1.0 - an.t) * v_new(i) + an.t * v_new(i + 1);
    const Vec3 xa = (1.0 - an.t) * state.positions[i] + an.t * state.positions[i + 1] + dt * va;
    f += (an.stiffness_n_per_m * (an.target_W - xa) +
          an.damping_n_s_per_m * (an.target_velocity_W - va))
             .dot(fr.axis_W);
  }
  return f;
}

// Stretch springs and their damping between neighbours. False for a zero-length segment.
bool assemble_stretch(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const int n = model.particle_count();
  const auto& x = state->positions;
  const auto& v = state->velocities;
  const double kl = model.stretch_stiffness();
  const double cl = model.settings().stretch_damping_n_s_per_m;
  const double l0 = model.rest_length_m();
  for (int i = 0; i + 1 < n; ++i) {
    const Vec3 e = x[i + 1] - x[i];
    const double l = e.norm();
    if (!(l > 0.0)) return false;
    const Vec3 t = e / l;
    const Mat3 tt = t * t.transpose();
    const Vec3 dv = v[i + 1] - v[i];
    const Vec3 f = (kl * (l - l0) + cl * dv.dot(t)) * t;  // on i, towards i + 1 when stretched
    add_rhs(state, i, f);
    add_rhs(state, i + 1, -f);
    const Mat3 k = kl * tt + kl * std::max(0.0, 1.0 - l0 / l) * (Mat3::Identity() - tt);
    const Mat3 a = dt * dt * k + dt * cl * tt;  // the coupling's share of M + dt D + dt² K
    add_block(&state->band, i, i, a);
    add_block(&state->band, i + 1, i + 1, a);
    add_block(&state->band, i + 1, i, -a);
    const Vec3 kv = k * (v[i + 1] - v[i]);  // −dt K v for this spring
    add_rhs(state, i, dt * kv);
    add_rhs(state, i + 1, -dt * kv);
  }
  return true;
}

// Bending: E = ½ k_b |r|², f = −k_b Jᵀ r, K ≈ k_b Jᵀ J (Gauss–Newton).
void assemble_bending(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const int n = model.particle_count();
  const auto& x = state->positions;
  const auto& v = state->velocities;
  const double kb = model.bending_stiffness();
  for (int i = 1; i + 1 < n; ++i) {
    const BendTerm b = bend_term(x[i - 1], x[i], x[i + 1]);
    const std::array<const Mat3*, 3> j = {&b.j0, &b.j1, &b.j2};
    const Vec3 jv = b.j0 * v[i - 1] + b.j1 * v[i] + b.j2 * v[i + 1];
    for (int p = 0; p < 3; ++p) {
      add_rhs(state, i - 1 + p,
              -kb * (j[p]->transpose() * b.r) - dt * kb * (j[p]->transpose() * jv));
      for (int q = 0; q <= p; ++q) {
        add_block(&state->band, i - 1 + p, i - 1 + q, dt * dt * kb * j[p]->transpose() * *j[q]);
      }
    }
  }
}

// Fixed particles: Δv = −v (they stop), decoupled from the rest. The coupling of a free row to a
// fixed one carries the fixed particle's known Δv = −v: with the fixed particles at rest (v = 0)
// that is nothing, which is how clamps are used.
void clamp_fixed_particles(const CatheterModel& model, CatheterState* state) noexcept {
  const int n = model.particle_count();
  const int dofs = 3 * n;
  const auto& v = state->velocities;
  for (int i = 0; i < n; ++i) {
    if (state->fixed[i] == 0) continue;
    for (int c = 0; c < 3; ++c) {
      const int row = 3 * i + c;
      for (int k = 1; k <= kHalfBand; ++k) {
        if (row - k >= 0) state->band[static_cast<size_t>(row) * kBandWidth + k] = 0.0;
        if (row + k < dofs) state->band[static_cast<size_t>(row + k) * kBandWidth + k] = 0.0;
      }
      state->band[static_cast<size_t>(row) * kBandWidth] = 1.0;
      state->rhs[row] = -v[i](c);
    }
  }
}

// Assembles (M + dt D + dt² K) Δv = dt (f − dt K v) in the band, clamps the fixed particles and
// solves; Δv in rhs.
bool assemble_and_solve(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  std::fill(state->band.begin(), state->band.end(), 0.0);
  assemble_particle_terms(model, state, dt);
  assemble_anchors(model, state, dt);
  assemble_links(state, dt);
  if (!assemble_stretch(model, state, dt)) return false;
  assemble_bending(model, state, dt);
  for (double& r : state->rhs) r *= dt;
  clamp_fixed_particles(model, state);
  return band_cholesky_solve(&state->band, &state->rhs, 3 * model.particle_count());
}

// One linearly implicit backward-Euler step; external forces are read, not cleared. Friction
// groups are solved sticking first; a group whose sticking force exceeds its limit slips, and
// the step is solved again.
bool implicit_step(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const int n = model.particle_count();
  std::fill(state->slipping.begin(), state->slipping.end(), false);
  if (!assemble_and_solve(model, state, dt)) return false;
  bool any_slip = false;
  for (int32_t g = 0; g < state->friction_count; ++g) {
    const double f = sticking_axial_force(model, *state, g, dt);
    const auto slot = static_cast<size_t>(g);
    state->friction_results[slot] = {false, f};
    if (std::abs(f) > state->frictions[slot].limit_n) {
      state->slipping[slot] = true;
      state->friction_results[slot].slipped = true;
      any_slip = true;
    }
  }
  if (any_slip && !assemble_and_solve(model, state, dt)) return false;
  for (int32_t g = 0; g < state->friction_count; ++g) {
    const auto slot = static_cast<size_t>(g);
    if (state->slipping[slot]) {
      state->friction_results[slot].axial_force_n = std::copysign(
          state->frictions[slot].limit_n, state->friction_results[slot].axial_force_n);
    }
  }
  auto& x = state->positions;
  auto& v = state->velocities;
  for (int i = 0; i < n; ++i) {
    const Vec3 dv = Eigen::Map<const Vec3>(state->rhs.data() + static_cast<ptrdiff_t>(3) * i);
    const Vec3 v1 = v[i] + dv;
    const Vec3 x1 = x[i] + dt * v1;
    if (!v1.allFinite() || !x1.allFinite()) return false;  // step_catheter restores
    v[i] = v1;
    x[i] = x1;
  }
  return true;
}

double total_energy(const CatheterModel& model, const CatheterState& state) {
  return catheter_energy(model, state) + catheter_gravity_energy(model, state);
}

// For the energy guard, the anchors of groups that slipped in the step: the axial part of their
// springs' energy at `positions` (free along the axis while slipping, so not energy the step
// holds), and the work their friction did from `before` to the positions now.
struct SlipTerms {
  double axial_energy_before = 0.0;
  double axial_energy_after = 0.0;
  double friction_work = 0.0;
};
SlipTerms slip_terms(const CatheterState& state, std::span<const Vec3> before) {
  SlipTerms t;
  for (int32_t g = 0; g < state.friction_count; ++g) {
    const auto slot = static_cast<size_t>(g);
    if (!state.slipping[slot]) continue;
    const AnchorFriction& fr = state.frictions[slot];
    const double share = state.friction_results[slot].axial_force_n / fr.anchor_count;
    for (int32_t a = fr.first_anchor; a < fr.first_anchor + fr.anchor_count; ++a) {
      const CenterlineAnchor& an = state.anchors[static_cast<size_t>(a)];
      const auto i = static_cast<size_t>(an.segment);
      const Vec3 x0 = (1.0 - an.t) * before[i] + an.t * before[i + 1];
      const Vec3 x1 = (1.0 - an.t) * state.positions[i] + an.t * state.positions[i + 1];
      const double d0 = (an.target_W - x0).dot(fr.axis_W);
      const double d1 = (an.target_W - x1).dot(fr.axis_W);
      t.axial_energy_before += 0.5 * an.stiffness_n_per_m * d0 * d0;
      t.axial_energy_after += 0.5 * an.stiffness_n_per_m * d1 * d1;
      t.friction_work += share * fr.axis_W.dot(x1 - x0);
    }
  }
  return t;
}

// The work a moving surface's friction did on the catheter in the step: its driving part
// c_t P v_s (the rest, −c_t P v, only dissipates), over each particle's displacement.
double surface_friction_work(const CatheterState& state, int depth, int n) {
  double work = 0.0;
  for (int i = 0; i < n; ++i) {
    const double ct = state.contact_friction_damping[i];
    if (ct == 0.0) continue;
    const Vec3& nc = state.contact_normal[i];
    const Vec3& vs = state.contact_surface_velocity[i];
    const Vec3 drive = ct * (vs - nc.dot(vs) * nc);
    work += drive.dot(state.positions[i] - state.saved_positions[depth * n + i]);
  }
  return work;
}

// The work the anchors' and links' dampers did in the step through their targets' own motion:
// c v_target (the rest, −c v, only dissipates), over each point's displacement.
double moving_target_work(const CatheterModel& model, const CatheterState& state, int depth,
                          int n) {
  const std::span<const Vec3> before(
      state.saved_positions.data() + static_cast<ptrdiff_t>(depth) * n, static_cast<size_t>(n));
  double work = 0.0;
  for (int32_t a = 0; a < state.anchor_count; ++a) {
    const CenterlineAnchor& an = state.anchors[static_cast<size_t>(a)];
    if (an.damping_n_s_per_m == 0.0 || an.target_velocity_W.isZero()) continue;
    const auto i = static_cast<size_t>(an.segment);
    if (an.segment < 0 || an.segment + 1 >= model.particle_count()) continue;
    const Vec3 moved = (1.0 - an.t) * (state.positions[i] - before[i]) +
                       an.t * (state.positions[i + 1] - before[i + 1]);
    work += an.damping_n_s_per_m * an.target_velocity_W.dot(moved);
  }
  for (int32_t l = 0; l < state.link_count; ++l) {
    const CenterlineLink& link = state.links[static_cast<size_t>(l)];
    if (link.damping_n_s_per_m == 0.0 || link.rest_velocity_W.isZero()) continue;
    const LinkWeights lw = link_weights(link);
    Vec3 moved = Vec3::Zero();
    for (int p = 0; p < lw.count; ++p) {
      const auto i = static_cast<size_t>(lw.particle[p]);
      moved += lw.coeff[p] * (state.positions[i] - before[i]);
    }
    work += link.damping_n_s_per_m * link.rest_velocity_W.dot(moved);
  }
  return work;
}

// Implicit step(s) over dt; a step that gains more energy than the external forces put in is
// redone as two half steps (linearly implicit Euler is dissipative only as dt shrinks on a
// strongly nonlinear, non-convex bending energy), down to dt / 2^depth.
bool guarded_step(const CatheterModel& model, CatheterState* state, double dt, int depth) noexcept {
  const int n = model.particle_count();
  for (int i = 0; i < n; ++i) {
    state->saved_positions[depth * n + i] = state->positions[i];
    state->saved_velocities[depth * n + i] = state->velocities[i];
  }
  double e0 = total_energy(model, *state);
  if (!implicit_step(model, state, dt)) return false;
  if (depth + 1 >= CatheterState::kGuardDepth) return true;
  double work = 0.0;
  for (int i = 0; i < n; ++i) {
    work +=
        state->external_force[i].dot(state->positions[i] - state->saved_positions[depth * n + i]);
  }
  const SlipTerms slip = slip_terms(
      *state,
      std::span<const Vec3>(state->saved_positions.data() + static_cast<ptrdiff_t>(depth) * n,
                            static_cast<size_t>(n)));
  work += slip.friction_work + surface_friction_work(*state, depth, n) +
          moving_target_work(model, *state, depth, n);
  const double e1 = total_energy(model, *state) - slip.axial_energy_after;
  e0 -= slip.axial_energy_before;
  // Rises below rounding (relative 1e-13, or 1e-16 J near rest) are not energy gained.
  if (e1 <= e0 + std::max(work, 0.0) + 1e-13 * std::abs(e0) + kEnergyFloorJ) return true;
  ++state->guard_refinements;
  for (int i = 0; i < n; ++i) {
    state->positions[i] = state->saved_positions[depth * n + i];
    state->velocities[i] = state->saved_velocities[depth * n + i];
  }
  return guarded_step(model, state, 0.5 * dt, depth + 1) &&
         guarded_step(model, state, 0.5 * dt, depth + 1);
}

}  // namespace

Eigen::Vector3d contact_friction_force(const CatheterState& state, int32_t i) {
  const auto k = static_cast<size_t>(i);
  if (k >= state.positions.size() || state.contact_stiffness[k] == 0.0) return Vec3::Zero();
  const Vec3& nc = state.contact_normal[k];
  const Vec3 rel = state.velocities[k] - state.contact_surface_velocity[k];
  return -state.contact_friction_damping[k] * (rel - nc.dot(rel) * nc);
}

bool step_catheter(const CatheterModel& model, CatheterState* state, double dt) noexcept {
  const bool valid_dt = std::isfinite(dt) && dt > 0.0;
  const bool ok = valid_dt && guarded_step(model, state, dt, 0);
  for (auto& f : state->external_force) f.setZero();
  if (!ok) {
    // Back where the step started (the guard's level-0 save), at rest.
    if (valid_dt) {
      std::copy_n(state->saved_positions.begin(), model.particle_count(), state->positions.begin());
    }
    for (auto& v : state->velocities) v.setZero();
  }
  return ok;
}

}  // namespace lap::models
