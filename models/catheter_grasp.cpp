#include "models/catheter_grasp.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace lap::models {
namespace {

Eigen::Vector3d to_jaw(const JawFrame& j, const Eigen::Vector3d& p_W) {
  return j.rotation_WJ.transpose() * (p_W - j.hinge_W);
}
Eigen::Vector3d to_world(const JawFrame& j, const Eigen::Vector3d& p_J) {
  return j.hinge_W + j.rotation_WJ * p_J;
}
double last_s(std::span<const Eigen::Vector3d> positions) {
  return static_cast<double>(positions.size()) - 1.0;
}

// The part [t0, t1] of the segment p0 → p1 (jaw frame) inside the wedge: depth 0..L, |z| ≤ w/2,
// |x| ≤ depth tan(half) + r. Cyrus–Beck clipping against the six half-spaces a·p + c ≤ 0.
bool clip_to_wedge(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double length,
                   double half_width, double tan_half, double radius, double* t0, double* t1) {
  const std::array<Eigen::Vector4d, 6> planes = {
      Eigen::Vector4d(0.0, 1.0, 0.0, 0.0),           // depth ≥ 0 (y ≤ 0)
      Eigen::Vector4d(0.0, -1.0, 0.0, -length),      // depth ≤ L
      Eigen::Vector4d(0.0, 0.0, 1.0, -half_width),   // z ≤ w/2
      Eigen::Vector4d(0.0, 0.0, -1.0, -half_width),  // z ≥ −w/2
      Eigen::Vector4d(1.0, tan_half, 0.0, -radius),  // x ≤ depth tan(half) + r
      Eigen::Vector4d(-1.0, tan_half, 0.0, -radius),
  };
  const Eigen::Vector3d d = p1 - p0;
  *t0 = 0.0;
  *t1 = 1.0;
  for (const Eigen::Vector4d& pl : planes) {
    const Eigen::Vector3d a = pl.head<3>();
    const double num = a.dot(p0) + pl.w();
    const double den = a.dot(d);
    if (den == 0.0) {
      if (num > 0.0) return false;
      continue;
    }
    const double t = -num / den;
    if (den < 0.0) {
      *t0 = std::max(*t0, t);
    } else {
      *t1 = std::min(*t1, t);
    }
    if (*t0 > *t1) return false;
  }
  return true;
}

// The gap the jaws leave the catheter's centre at `depth` along x: |x| ≤ depth tan(half) − r.
double centre_gap(const GraspSettings& s, double depth, double half_rad, double radius) {
  return std::max(0.0, std::clamp(depth, 0.0, s.jaw_length_m) * std::tan(half_rad) - radius);
}

// Moves v towards `to` by at most `step`.
double approach(double v, double to, double step) { return v + std::clamp(to - v, -step, step); }

// The jaws flatten the held section into the gap between them as they close: its centre into
// the gap, its axis turned towards the mid-plane (its length kept) until its ends are inside.
void flatten(const GraspSettings& s, const JawFrame& jaws, double radius, GraspState* g) {
  const double half = 0.5 * jaws.opening_rad;
  Eigen::Vector3d& c = g->center_J;
  const double gap_c = centre_gap(s, -c.y(), half, radius);
  c.x() = approach(c.x(), std::clamp(c.x(), -gap_c, gap_c), s.flatten_step_m);
  const double h = g->half_length_m;
  const double gap_ends = std::min(centre_gap(s, -held_end_J(*g, 0).y(), half, radius),
                                   centre_gap(s, -held_end_J(*g, 1).y(), half, radius));
  Eigen::Vector3d& a = g->axis_J;
  const double limit = h > 0.0 ? gap_ends / h : 1.0;
  a.x() = approach(a.x(), std::clamp(a.x(), -limit, limit), s.flatten_step_m / std::max(h, 1e-6));
  const double in_plane = std::hypot(a.y(), a.z());
  const double keep = std::sqrt(std::max(0.0, 1.0 - a.x() * a.x()));
  if (in_plane > 1e-12) {
    a.y() *= keep / in_plane;
    a.z() *= keep / in_plane;
  } else {
    a.z() = keep;  // along the jaws' opening: laid across them
  }
}

void capture(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
             std::span<const Eigen::Vector3d> positions, GraspState* g) {
  const double wedge = std::max(g->closing_from_rad, jaws.opening_rad);
  const HeldSection sec = section_between_jaws(s, jaws, wedge, model, positions);
  if (!sec.found()) return;
  // Held: the section's extent in the jaws' mid-plane (a catheter crossing through the jaws
  // is pinched over their width), at least the jaw's width.
  const Eigen::Vector3d e0 = to_jaw(jaws, point_at(positions, sec.s0));
  const Eigen::Vector3d e1 = to_jaw(jaws, point_at(positions, sec.s1));
  const double half_m =
      std::max(0.5 * std::hypot(e1.y() - e0.y(), e1.z() - e0.z()), 0.5 * s.jaw_width_m);
  const double half = half_m / model.rest_length_m();
  const double end = last_s(positions);
  if (2.0 * half > end) return;
  g->half_length_s = half;
  g->half_length_m = half_m;
  g->center_s = std::clamp(0.5 * (sec.s0 + sec.s1), half, end - half);
  // Held where its ends are now (no force step on catching it); flatten() lays it between
  // the jaws.
  const Eigen::Vector3d a = to_jaw(jaws, point_at(positions, g->center_s - half));
  const Eigen::Vector3d b = to_jaw(jaws, point_at(positions, g->center_s + half));
  g->center_J = 0.5 * (a + b);
  g->axis_J =
      (b - a).norm() > 1e-12 ? Eigen::Vector3d((b - a).normalized()) : Eigen::Vector3d::UnitZ();
  g->held = true;
  g->sliding = false;
  g->slid_m = 0.0;
}

// The held points: the section's two ends and the particles between them (on the catheter).
template <typename Visit>
void for_each_held_point(const GraspState& g, std::span<const Eigen::Vector3d> positions,
                         Visit visit) {
  const double s0 = std::max(held_end_s(g, 0), 0.0);
  const double s1 = std::min(held_end_s(g, 1), last_s(positions));
  visit(s0);
  for (double p = std::floor(s0) + 1.0; p < s1; p += 1.0) visit(p);
  visit(s1);
}

// The held points' mean offset from where the jaws hold them, along the held axis (material
// ahead of its place on the line: > 0), and how many there are.
double mean_axial_offset(const JawFrame& jaws, std::span<const Eigen::Vector3d> positions,
                         const GraspState& g, const Eigen::Vector3d& axis, int* count) {
  double sum = 0.0;
  *count = 0;
  for_each_held_point(g, positions, [&](double at) {
    sum += (point_at(positions, at) - to_world(jaws, held_point_J(g, at))).dot(axis);
    ++*count;
  });
  return *count > 0 ? sum / *count : 0.0;
}

// After a step in which the held section slipped (Coulomb, solved in the catheter's step:
// catheter_model.h), the held material is re-read where it now lies at the jaws: the
// section's material coordinate moves by the axial slide. The slip is between the catheter and
// the jaws' faces; the coupling to the hand (the anchors) stays stretched by what it carries,
// the friction F: the offset is reset to F / k_c, not to zero (reset to zero, the soft coupling
// would let the catheter run F / k_c further every step it slips).
void follow_slide(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
                  std::span<const Eigen::Vector3d> positions, GraspState* g) {
  const Eigen::Vector3d axis = jaws.rotation_WJ * g->axis_J;  // towards increasing s
  int count = 0;
  const double offset = mean_axial_offset(jaws, positions, *g, axis, &count);
  // The friction on the catheter, −slide_sign F along the axis, is what the anchors bear once
  // it sticks: −k_c × the offset.
  const double carried = s.coupling_stiffness_n_per_m > 0.0
                             ? g->slide_sign * g->friction_n / s.coupling_stiffness_n_per_m
                             : 0.0;
  // Moving the held material by Δ along the centre line moves its points by Δ τ: the axial
  // offset changes by (τ · axis) Δ.
  const Eigen::Vector3d chord =
      point_at(positions, held_end_s(*g, 1)) - point_at(positions, held_end_s(*g, 0));
  const double along = std::max(chord.normalized().dot(axis), 0.3);
  const double shift_m = -(offset - carried) / along;
  g->center_s += shift_m / model.rest_length_m();
  g->slid_m += std::abs(shift_m);
}

// The held points' material coordinates, in order (the section's ends and the particles
// between them); at most kMaxHeldPoints (a section longer than the jaws has no more).
constexpr int kMaxHeldPoints = 8;
struct HeldPoints {
  std::array<double, kMaxHeldPoints> s{};
  int count = 0;
};
HeldPoints held_points(const GraspState& g, std::span<const Eigen::Vector3d> positions) {
  HeldPoints h;
  for_each_held_point(g, positions, [&](double at) {
    if (h.count < kMaxHeldPoints) h.s[static_cast<size_t>(h.count++)] = at;
  });
  return h;
}

// A centre-line point (segment, t) for material coordinate `at`.
void locate(const CatheterModel& model, double at, int32_t* segment, double* t) {
  *segment = std::clamp(static_cast<int32_t>(at), 0, model.particle_count() - 2);
  *t = std::clamp(at - *segment, 0.0, 1.0);
}

// Holds the section: each held point's anchor, its share of the coupling's spring and damper
// towards its place on the held line in the jaws read for this step (their velocity from the
// jaws at the last step); the links between consecutive points keeping the line's shape and
// turn. Adds the anchors' reaction to the tool's wrench (the model's step decides whether they
// stick).
void hold_section(const GraspSettings& s, const JawFrame& jaws, const JawFrame& jaws_before,
                  double dt, const CatheterModel& model, const GraspState& g, CatheterState* cath,
                  GraspOutput* out) {
  const HeldPoints h = held_points(g, cath->positions);
  if (h.count == 0) return;
  const double k = s.coupling_stiffness_n_per_m / h.count;
  const double c = s.coupling_damping_n_s_per_m / h.count;
  const double rate = dt > 0.0 ? 1.0 / dt : 0.0;
  const std::span<const Eigen::Vector3d> positions(cath->positions);
  const std::span<const Eigen::Vector3d> velocities(cath->velocities);
  for (int i = 0; i < h.count; ++i) {
    const double at = h.s[static_cast<size_t>(i)];
    const Eigen::Vector3d p_J = held_point_J(g, at);
    CenterlineAnchor a;
    locate(model, at, &a.segment, &a.t);
    a.target_W = to_world(jaws, p_J);
    a.target_velocity_W = (a.target_W - to_world(jaws_before, p_J)) * rate;
    a.stiffness_n_per_m = k;
    a.damping_n_s_per_m = c;
    if (!add_anchor(model, a, cath)) continue;
    const Eigen::Vector3d x = point_at(positions, at);
    const Eigen::Vector3d v = point_at(velocities, at);
    const Eigen::Vector3d on_tool = -(k * (a.target_W - x) + c * (a.target_velocity_W - v));
    out->force_on_tool_W += on_tool;
    out->torque_on_tool_W += (a.target_W - jaws.hinge_W).cross(on_tool);
  }
  for (int i = 0; i + 1 < h.count; ++i) {
    const double sa = h.s[static_cast<size_t>(i)];
    const double sb = h.s[static_cast<size_t>(i) + 1];
    const Eigen::Vector3d d_J = held_point_J(g, sb) - held_point_J(g, sa);
    CenterlineLink l;
    locate(model, sa, &l.segment_a, &l.t_a);
    locate(model, sb, &l.segment_b, &l.t_b);
    l.rest_W = jaws.rotation_WJ * d_J;
    l.rest_velocity_W = (l.rest_W - jaws_before.rotation_WJ * d_J) * rate;
    l.stiffness_n_per_m = s.hold_stiffness_n_per_m;
    l.damping_n_s_per_m = s.hold_damping_n_s_per_m;
    (void)add_link(model, l, cath);
  }
}

}  // namespace

double held_end_s(const GraspState& grasp, int k) {
  return k == 0 ? grasp.center_s - grasp.half_length_s : grasp.center_s + grasp.half_length_s;
}

Eigen::Vector3d held_point_J(const GraspState& grasp, double s) {
  const double along = grasp.half_length_s > 0.0 ? (s - grasp.center_s) / grasp.half_length_s : 0.0;
  return grasp.center_J + along * grasp.half_length_m * grasp.axis_J;
}

Eigen::Vector3d held_end_J(const GraspState& grasp, int k) {
  return k == 0 ? Eigen::Vector3d(grasp.center_J - grasp.half_length_m * grasp.axis_J)
                : Eigen::Vector3d(grasp.center_J + grasp.half_length_m * grasp.axis_J);
}

Eigen::Vector3d point_at(std::span<const Eigen::Vector3d> positions, double s) {
  if (positions.size() < 2) return positions.empty() ? Eigen::Vector3d::Zero() : positions[0];
  const double c = std::clamp(s, 0.0, last_s(positions));
  const auto i = std::min(static_cast<size_t>(c), positions.size() - 2);
  const double t = c - static_cast<double>(i);
  return (1.0 - t) * positions[i] + t * positions[i + 1];
}

HeldSection section_between_jaws(const GraspSettings& s, const JawFrame& jaws, double wedge_rad,
                                 const CatheterModel& model,
                                 std::span<const Eigen::Vector3d> positions) noexcept {
  const double tan_half = std::tan(std::clamp(0.5 * wedge_rad, 0.0, 1.4));
  HeldSection best;
  HeldSection piece;
  Eigen::Vector3d p0 = positions.empty() ? Eigen::Vector3d::Zero() : to_jaw(jaws, positions[0]);
  for (size_t i = 0; i + 1 < positions.size(); ++i) {
    const Eigen::Vector3d p1 = to_jaw(jaws, positions[i + 1]);
    double t0 = 0.0;
    double t1 = 0.0;
    if (clip_to_wedge(p0, p1, s.jaw_length_m, 0.5 * s.jaw_width_m, tan_half, model.radius_m(), &t0,
                      &t1)) {
      const double a = static_cast<double>(i) + t0;
      const double b = static_cast<double>(i) + t1;
      if (piece.found() && a <= piece.s1 + 1e-9) {
        piece.s1 = b;  // continues the piece
      } else {
        piece = {a, b};
      }
      if (!best.found() || piece.s1 - piece.s0 > best.s1 - best.s0) best = piece;
    }
    p0 = p1;
  }
  return best;
}

GraspOutput update_grasp(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
                         CatheterState* cath, GraspState* grasp, double dt) noexcept {
  GraspOutput out;
  const std::span<const Eigen::Vector3d> positions(cath->positions);
  // The opening from which the jaws are closing: a new peak whenever they open.
  if (jaws.opening_rad >= grasp->last_opening_rad) grasp->closing_from_rad = jaws.opening_rad;
  grasp->last_opening_rad = jaws.opening_rad;
  if (grasp->held && jaws.opening_rad > s.release_above_rad) {
    grasp->held = false;
    out.released_now = true;
  }
  if (!grasp->held && jaws.opening_rad < s.grasp_below_rad) {
    capture(s, jaws, model, positions, grasp);
    out.grasped_now = grasp->held;
  }
  if (!grasp->held) return out;
  // Follow a slide in the last step, then flatten the section further (flattening moves it
  // across the catheter, not along: it is no pull).
  if (grasp->sliding) follow_slide(s, grasp->jaws, model, positions, grasp);
  out.squeeze_n = grasp_squeeze(s, jaws, model, *grasp);
  flatten(s, jaws, model.radius_m(), grasp);
  // The jaws' motion since the last step, for the dampers (none on the step that caught it).
  const JawFrame before = out.grasped_now ? jaws : grasp->jaws;
  grasp->jaws = jaws;
  if (grasp->center_s < 0.0 || grasp->center_s > last_s(positions)) {
    grasp->held = false;  // slid off the end
    grasp->sliding = false;
    out.slipped_out = true;
    out.squeeze_n = 0.0;
    return out;
  }
  // The section's two ends and the particles between them, each tied to its place on the held
  // line (the jaws keep the section straight: a particle left free inside it would be a hinge),
  // with Coulomb friction 2 μ N along it, two jaw faces each pressed by the squeeze.
  const int32_t first = cath->anchor_count;
  hold_section(s, jaws, before, dt, model, *grasp, cath, &out);
  grasp->friction_slot = add_anchor_friction(jaws.rotation_WJ * grasp->axis_J,
                                             2.0 * s.friction * out.squeeze_n, first, cath);
  out.sliding = grasp->sliding;
  return out;
}

void finish_grasp_step(const CatheterState& catheter, GraspState* grasp) noexcept {
  const int32_t slot = grasp->friction_slot;
  if (!grasp->held || slot < 0 || slot >= catheter.friction_count) {
    grasp->sliding = false;
    grasp->friction_n = 0.0;
    return;
  }
  const AnchorFrictionResult& r = catheter.friction_results[static_cast<size_t>(slot)];
  grasp->sliding = r.slipped;
  grasp->friction_n = r.slipped ? std::abs(r.axial_force_n) : 0.0;
  // The friction on the catheter resists the slide: the catheter moves against it.
  grasp->slide_sign = r.axial_force_n > 0.0 ? -1.0 : 1.0;
}

double grasp_squeeze(const GraspSettings& s, const JawFrame& jaws, const CatheterModel& model,
                     const GraspState& grasp) noexcept {
  if (!grasp.held) return 0.0;
  // The jaws' gap at the held section's depth against the catheter's diameter.
  const double depth = std::clamp(-grasp.center_J.y(), 0.0, s.jaw_length_m);
  const double gap = 2.0 * depth * std::sin(0.5 * jaws.opening_rad);
  return s.squeeze_stiffness_n_per_m * std::max(0.0, 2.0 * model.radius_m() - gap);
}

GraspWrench coupling_wrench(const GraspSettings& s, const HapticJaws& now,
                            const CatheterModel& model, const CatheterMotion& catheter,
                            const GraspState& grasp) noexcept {
  GraspWrench w;
  const auto n = static_cast<size_t>(model.particle_count());
  if (!grasp.held || catheter.positions.size() != n || catheter.velocities.size() != n ||
      !(now.tick_s > 0.0)) {
    return w;
  }
  const HeldPoints h = held_points(grasp, catheter.positions);
  if (h.count == 0) return w;
  const double k = s.coupling_stiffness_n_per_m / h.count;
  const double c = s.coupling_damping_n_s_per_m / h.count;
  const Eigen::Vector3d axis = grasp.jaws.rotation_WJ * grasp.axis_J;
  const Eigen::Matrix3d across =
      grasp.sliding ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - axis * axis.transpose())
                    : Eigen::Matrix3d::Identity();
  // The anchors: the coupling's spring and damper between the jaws now and each held point as
  // the model left it; while the section slid, the friction it met along the axis instead.
  Eigen::Vector3d on_catheter_total = Eigen::Vector3d::Zero();
  for (int i = 0; i < h.count; ++i) {
    const double at = h.s[static_cast<size_t>(i)];
    const Eigen::Vector3d p_J = held_point_J(grasp, at);
    const Eigen::Vector3d target = to_world(now.jaws, p_J);
    const Eigen::Vector3d target_velocity = (target - to_world(now.jaws_before, p_J)) / now.tick_s;
    const Eigen::Vector3d x = point_at(catheter.positions, at);
    const Eigen::Vector3d v = point_at(catheter.velocities, at);
    Eigen::Vector3d on_catheter = across * (k * (target - x) + c * (target_velocity - v));
    if (grasp.sliding) on_catheter -= grasp.slide_sign * grasp.friction_n / h.count * axis;
    on_catheter_total += on_catheter;
    w.torque_W -= (target - now.jaws.hinge_W).cross(on_catheter);
  }
  // The links: no net force; the moment of their springs and dampers on the jaws' turn, the
  // reaction of F = k (r − d) + c (ṙ − ḋ) at the pair's places in the jaws: −r × F.
  for (int i = 0; i + 1 < h.count; ++i) {
    const double sa = h.s[static_cast<size_t>(i)];
    const double sb = h.s[static_cast<size_t>(i) + 1];
    const Eigen::Vector3d d_J = held_point_J(grasp, sb) - held_point_J(grasp, sa);
    const Eigen::Vector3d r = now.jaws.rotation_WJ * d_J;
    const Eigen::Vector3d r_velocity = (r - now.jaws_before.rotation_WJ * d_J) / now.tick_s;
    const Eigen::Vector3d d = point_at(catheter.positions, sb) - point_at(catheter.positions, sa);
    const Eigen::Vector3d d_velocity =
        point_at(catheter.velocities, sb) - point_at(catheter.velocities, sa);
    const Eigen::Vector3d f =
        s.hold_stiffness_n_per_m * (r - d) + s.hold_damping_n_s_per_m * (r_velocity - d_velocity);
    w.torque_W -= r.cross(f);
  }
  const double norm = on_catheter_total.norm();
  const double scale = norm > s.max_force_n ? s.max_force_n / norm : 1.0;
  w.force_W = -scale * on_catheter_total;
  w.torque_W *= scale;
  if (!w.force_W.allFinite() || !w.torque_W.allFinite()) return {};
  return w;
}

double coupling_rotational_stiffness(const GraspSettings& s, const CatheterModel& model,
                                     std::span<const Eigen::Vector3d> positions,
                                     const GraspState& grasp) noexcept {
  if (!grasp.held || positions.size() != static_cast<size_t>(model.particle_count())) return 0.0;
  const HeldPoints h = held_points(grasp, positions);
  double k = 0.0;
  for (int i = 0; i + 1 < h.count; ++i) {
    const Eigen::Vector3d d_J = held_point_J(grasp, h.s[static_cast<size_t>(i) + 1]) -
                                held_point_J(grasp, h.s[static_cast<size_t>(i)]);
    k += s.hold_stiffness_n_per_m * d_J.squaredNorm();
  }
  return k;
}

}  // namespace lap::models
