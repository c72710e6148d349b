#include "sim/authoring/expert_run.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>

namespace lap::sim {

std::string_view to_string(ExpertMistake mistake) {
  switch (mistake) {
    case ExpertMistake::kNone:
      return "";
    case ExpertMistake::kDropsCatheter:
      return "drop";
    case ExpertMistake::kOvershoots:
      return "overshoot";
    case ExpertMistake::kTearsDuct:
      return "tear";
    case ExpertMistake::kEntersCommonBileDuct:
      return "cbd";
    case ExpertMistake::kHesitates:
      return "time_limit";
  }
  return "";
}

std::optional<ExpertMistake> parse_mistake(std::string_view name) {
  for (const ExpertMistake m : kClumsyRuns) {
    if (to_string(m) == name) return m;
  }
  return std::nullopt;
}

namespace {

using V = Eigen::Vector3d;

double smoothstep(double s) { return 0.5 - 0.5 * std::cos(std::numbers::pi * s); }

// A tool through its port: its jaws' frame J (x the opening, y along the shaft to the handle,
// z = x × y; sim/runtime/trocar_tool.h) for a hinge and a roll.
struct PortTool {
  V port_W = V::Zero();
  double shaft_length_m = 0.36;

  [[nodiscard]] V shaft_dir(const V& hinge) const { return (port_W - hinge).normalized(); }
  [[nodiscard]] Eigen::Matrix3d frame(const V& hinge, const V& roll_x) const {
    const V y = shaft_dir(hinge);
    const V x = (roll_x - roll_x.dot(y) * y).normalized();
    Eigen::Matrix3d r;
    r << x, y, x.cross(y);
    return r;
  }
  // The device's keyframe for a hinge, a roll (the device's x axis) and a grip.
  [[nodiscard]] hardware::Keyframe keyframe(double t, const V& hinge, const V& roll_x,
                                            double grip) const {
    const V u = -shaft_dir(hinge);
    const double inside = (hinge - port_W).norm();
    hardware::Keyframe k;
    k.time_s = t;
    k.position_W = port_W - (shaft_length_m - inside) * u;
    const V x = frame(hinge, roll_x).col(0);
    k.orientation_W = Eigen::Quaterniond::FromTwoVectors(V::UnitX(), x);
    k.gripper_angle_rad = grip;
    return k;
  }
};

// The hinge that puts a point `depth` along the jaws (their mid-plane) at `held`.
V hinge_holding(const PortTool& tool, const V& held, double depth) {
  V h = held;
  for (int i = 0; i < 50; ++i) h = held + depth * tool.shaft_dir(h);
  return h;
}

// The catheter in the jaws' frame: its tip and its direction towards the tip.
struct HeldCatheter {
  V tip_J = V::Zero();
  V dir_J = V::UnitZ();
};

struct Pose {
  V hinge = V::Zero();
  V roll_x = V::UnitX();
  double error_deg = 0.0;  // between the wanted direction and the one achieved
  V achieved_dir = V::UnitZ();
};

// The pose with the held tip at `tip` and the held direction nearest `dir`: about the shaft the
// roll φ that maximises the in-plane alignment (closed form), then the hinge that puts the tip
// there (fixed point: the shaft's direction depends on the hinge).
Pose solve_pose(const PortTool& tool, const HeldCatheter& held, const V& tip, const V& dir,
                const V& hinge_guess) {
  Pose pose;
  pose.hinge = hinge_guess;
  for (int it = 0; it < 60; ++it) {
    const V y = tool.shaft_dir(pose.hinge);
    const V p = y.unitOrthogonal();
    const V q = y.cross(p);
    // x = cos φ p + sin φ q gives z = x × y = sin φ p − cos φ q.
    const double a = dir.dot(p);
    const double b = dir.dot(q);
    const double dx = held.dir_J.x();
    const double dz = held.dir_J.z();
    const double phi = std::atan2(a * dz + b * dx, a * dx - b * dz);
    pose.roll_x = std::cos(phi) * p + std::sin(phi) * q;
    const Eigen::Matrix3d r = tool.frame(pose.hinge, pose.roll_x);
    const V next = tip - r * held.tip_J;
    const bool done = (next - pose.hinge).norm() < 1e-10;
    pose.hinge = next;
    if (done) break;
  }
  const Eigen::Matrix3d r = tool.frame(pose.hinge, pose.roll_x);
  pose.achieved_dir = r * held.dir_J;
  pose.error_deg =
      std::acos(std::clamp(pose.achieved_dir.dot(dir), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  return pose;
}

// What the plan is made from: the incision and the line in, the catheter as it lies.
struct Geometry {
  const models::IncisionRim* rim = nullptr;
  Eigen::Isometry3d pose_WD = Eigen::Isometry3d::Identity();
  V incision = V::Zero();  ///< its centre on the wall's mid-surface
  V normal = V::UnitZ();   ///< out of the duct there
  V axis = V::UnitZ();     ///< along the duct, towards its end further from the incision
  V in_dir = V::UnitZ();   ///< the line in: at the entry slant to the axis, into the wall
  V cath_tip = V::Zero();
  V cath_dir = V::UnitZ();  ///< towards the tip
  double jaw_mid_m = 0.01;
};

Geometry measure(const SessionModel& model, const ExpertRunSettings& settings) {
  Geometry g;
  g.rim = &model.tissue().duct().rim;
  const models::IncisionRim& rim = *g.rim;
  g.pose_WD = rim.pose_DW.inverse();
  g.incision = g.pose_WD * V(rim.mid_radius_m * std::cos(rim.angle_rad),
                             rim.mid_radius_m * std::sin(rim.angle_rad), rim.z_m);
  g.normal = g.pose_WD.linear() * V(std::cos(rim.angle_rad), std::sin(rim.angle_rad), 0.0);
  g.axis =
      (rim.z_m < 0.5 * rim.length_m ? 1.0 : -1.0) * (g.pose_WD.linear() * V::UnitZ()).normalized();
  const double slant = settings.entry_slant_deg * std::numbers::pi / 180.0;
  g.in_dir = (std::cos(slant) * g.axis - std::sin(slant) * g.normal).normalized();
  const TissueWorldSettings& ws = model.tissue().settings();
  g.cath_dir = ws.catheter_direction_W.normalized();
  g.cath_tip = ws.catheter_start_W + ws.catheter.length_m * g.cath_dir;
  g.jaw_mid_m = 0.5 * model.tool(1).gripper.jaw_length_m;
  return g;
}

struct Planner {
  const ExpertRunSettings& s;
  const Geometry& g;
  PortTool right;
  PortTool left;
  ExpertRun run;
  double time_limit_s = 600.0;  ///< the task's (the hesitant run outlasts it)
  const haptics::MeshDatabase* cbd_surface = nullptr;   ///< the common bile duct, where named
  const haptics::MeshDatabase* duct_surface = nullptr;  ///< the cystic duct, at rest
  V camera_W = V::Zero();

  // The right hand's hinges and rolls as keyed, and from which keyframe it holds the catheter
  // (`hold_J`: the held catheter in the jaws' frame), for the clearances measured afterwards.
  std::vector<std::pair<V, V>> right_poses{};
  size_t holding_from = SIZE_MAX;
  HeldCatheter hold_J{};

  void key(hardware::ScriptedTrajectory* traj, const PortTool& tool, double time, const V& hinge,
           const V& roll_x, double grip) {
    traj->keyframes.push_back(tool.keyframe(time, hinge, roll_x, grip));
    if (traj == &run.right) right_poses.emplace_back(hinge, roll_x);
  }

  // The least signed distance (negative inside) from the points of segment a-b (every 1 mm) to
  // every organ but the duct, into *c where less than it already holds.
  static void measure_clearance(const std::vector<const haptics::MeshDatabase*>& organs,
                                int32_t duct, const V& a, const V& b, double time_s,
                                PlannedClearance* c) {
    // At most 1 mm apart: a length of whole millimetres (the held catheter's 25 mm) rounded
    // a little over is not one more interval.
    const double length = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(length / 0.001 - 1e-6)));
    for (size_t o = 0; o < organs.size(); ++o) {
      if (static_cast<int32_t>(o) == duct) continue;
      for (int i = 0; i <= n; ++i) {
        const V x = a + (b - a) * (static_cast<double>(i) / n);
        V q;
        if (organs[o]->nearest_face(x, &q, nullptr) < 0) continue;
        // Signed: inside the (closed) organ when the first face a ray from the point meets is
        // met from behind. The ray's direction is fixed and askew to the axes, so that it seldom
        // grazes an edge of the generated meshes. (The nearest face's side says nothing where
        // the nearest point is on an edge or a corner.)
        const V ray = V(0.31, 0.83, 0.47).normalized();
        const haptics::MeshDatabase::Crossing out = organs[o]->first_crossing(x, x + ray, true);
        const double d = out.face >= 0 && !out.from_front ? -(q - x).norm() : (q - x).norm();
        if (d < c->least_m) {
          c->least_m = d;
          c->organ = static_cast<int32_t>(o);
          c->time_s = time_s;
        }
      }
    }
  }

  // The right hand's clearances (ExpertRun::right_shaft, held_catheter), keyframe by keyframe.
  void measure_right_clearances(const SessionModel& model) {
    const std::vector<const haptics::MeshDatabase*> organs = model.rest_databases();
    const int32_t duct = model.tissue().duct_organ();
    const auto& keys = run.right.keyframes;
    for (size_t k = 0; k < right_poses.size() && k < keys.size(); ++k) {
      const auto& [hinge, roll_x] = right_poses[k];
      const double t = keys[k].time_s;
      measure_clearance(organs, duct, right.port_W, hinge, t, &run.right_shaft);
      if (k < holding_from || keys[k].gripper_angle_rad > s.grip_closed_rad) continue;
      const Eigen::Matrix3d frame = right.frame(hinge, roll_x);
      const V tip = hinge + frame * hold_J.tip_J;
      const V held = hinge + frame * V(0.0, -s.grasp_depth * 2.0 * g.jaw_mid_m, 0.0);
      measure_clearance(organs, duct, held, tip, t, &run.held_catheter);
    }
  }
  [[nodiscard]] int steps(double duration) const {
    return std::max(1, static_cast<int>(std::lround(duration / s.keyframe_step_s)));
  }
  // The hinge, roll and grip eased from one to the other over `duration`.
  void move(hardware::ScriptedTrajectory* traj, const PortTool& tool, double duration, const V& h0,
            const V& h1, const V& x0, const V& x1, double g0, double g1) {
    const int n = steps(duration);
    const double t0 = traj->keyframes.empty() ? 0.0 : traj->keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double e = smoothstep(static_cast<double>(k) / n);
      const V x = ((1.0 - e) * x0 + e * x1).normalized();
      key(traj, tool, t0 + duration * k / n, h0 + e * (h1 - h0), x, g0 + e * (g1 - g0));
    }
  }
  // Where the right hand's jaws go in: 5 cm inside its port towards `towards`.
  [[nodiscard]] V right_entry(const V& towards) const {
    return right.port_W + 0.05 * (towards - right.port_W).normalized();
  }

  // The right hand: over the catheter with the jaws open, down onto it, close; the tip carried
  // round in front of the incision and onto the line in; pushed along it; held. Returns the
  // end of the run.
  double catheter_hand() {
    const V held = g.cath_tip - s.grasp_from_tip_m * g.cath_dir;
    const V hinge = hinge_holding(right, held, s.grasp_depth * 2.0 * g.jaw_mid_m);
    const V x = right.shaft_dir(hinge).cross(g.cath_dir).normalized();
    const Eigen::Matrix3d frame = right.frame(hinge, x);
    const HeldCatheter hold{frame.transpose() * (g.cath_tip - hinge),
                            frame.transpose() * g.cath_dir};
    hardware::ScriptedTrajectory& r = run.right;
    const V above = hinge + 0.02 * right.shaft_dir(hinge);
    const V entry = right_entry(above);
    const double open = s.grip_open_rad;
    const double closed = s.grip_closed_rad;
    key(&r, right, 0.0, entry, x, open);
    move(&r, right, 1.5, entry, above, x, x, open, open);
    move(&r, right, 1.0, above, hinge, x, x, open, open);
    holding_from = right_poses.size();  // from the jaws' closing on (once shut: closed)
    hold_J = hold;
    move(&r, right, 0.5, hinge, hinge, x, x, open, closed);
    move(&r, right, 0.5, hinge, hinge, x, x, closed, closed);
    Pose pose{hinge, x, 0.0, g.cath_dir};
    if (s.mistake == ExpertMistake::kEntersCommonBileDuct)
      return into_common_bile_duct(hold, &pose);
    const V out_front = g.incision - 0.025 * g.in_dir + 0.01 * g.normal;
    const V start = g.incision - s.start_out_m * g.in_dir;
    carry(hold, &pose, 2.5, g.cath_tip, out_front, g.cath_dir, g.in_dir);
    if (s.mistake == ExpertMistake::kDropsCatheter) {
      // The jaws open on the way and stay open: from here on every keyframe lets go.
      const size_t from = r.keyframes.size() - 10;
      for (size_t k = from; k < r.keyframes.size(); ++k) {
        const double e = smoothstep(static_cast<double>(k - from + 1) / 10.0);
        r.keyframes[k].gripper_angle_rad = closed + e * (open - closed);
      }
    }
    carry(hold, &pose, 1.5, out_front, start, g.in_dir, g.in_dir);
    along_line(hold, &pose, 0.5, -s.start_out_m, -s.start_out_m);
    if (s.mistake == ExpertMistake::kHesitates) return hesitate(hold, &pose);
    // The clumsy push goes on 2 cm past where the expert stops, as fast.
    const double advance = s.advance_m + (s.mistake == ExpertMistake::kOvershoots ? 0.02 : 0.0);
    along_line(hold, &pose, 6.0 * advance / s.advance_m, -s.start_out_m, advance - s.start_out_m);

    if (s.mistake == ExpertMistake::kDropsCatheter) {
      for (hardware::Keyframe& k : r.keyframes) {
        if (k.time_s > 6.0) k.gripper_angle_rad = open;
      }
    }
    hardware::Keyframe last = r.keyframes.back();
    last.time_s += s.hold_after_s;
    r.keyframes.push_back(last);
    return last.time_s;
  }

  // The clumsy hand that takes the common bile duct beside the cystic duct for it: the tip
  // carried in front of the common bile duct's wall, pointing into it, and pushed on through the
  // wall into its lumen. The wall: facing the laparoscope, cbd_clear_m on from the junction with
  // the cystic duct along the common bile duct (at the junction the cystic duct is in the way).
  // Returns the end of the run.
  double into_common_bile_duct(const HeldCatheter& hold, Pose* pose) {
    const haptics::MeshDatabase& cbd = *cbd_surface;
    // The common bile duct's axis: its vertices' principal direction.
    V centre = V::Zero();
    for (int32_t v = 0; v < cbd.vertex_count(); ++v) centre += cbd.position(v);
    centre /= std::max(1, cbd.vertex_count());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (int32_t v = 0; v < cbd.vertex_count(); ++v) {
      const V d = cbd.position(v) - centre;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    V along = eig.eigenvectors().col(2);
    // Where the cystic duct meets it (the axis' point nearest the incision), and from there
    // along the common bile duct away from the gallbladder (towards the duodenum: away from the
    // incision's side of the duct), cbd_clear_m on.
    const V junction = centre + along.dot(g.incision - centre) * along;
    if (along.dot(g.axis) < 0.0) along = -along;
    const V aim = junction + s.cbd_clear_m * along;
    V wall = aim;
    const int32_t f = cbd.nearest_face(aim + 0.02 * (camera_W - aim).normalized(), &wall, nullptr);
    const V out = f >= 0 ? V(cbd.face_normal(f)) : g.normal;
    const V front = wall + 0.012 * out;
    carry(hold, pose, 2.5, g.cath_tip, front, g.cath_dir, -out);
    carry(hold, pose, 1.5, front, wall + 0.008 * out, -out, -out);
    carry(hold, pose, 3.0, wall + 0.008 * out, wall - s.cbd_push_m * out, -out, -out);
    hardware::ScriptedTrajectory& r = run.right;
    hardware::Keyframe last = r.keyframes.back();
    last.time_s += s.hold_after_s;
    r.keyframes.push_back(last);
    return last.time_s;
  }

  // The clumsy hand that brings the tip in front of the incision and hesitates: it draws back
  // and comes up again three times, never going in, then stays there until the time limit has
  // passed. Returns the end of the run.
  double hesitate(const HeldCatheter& hold, Pose* pose) {
    const double back = -s.start_out_m - 0.006;
    for (int k = 0; k < 3; ++k) {
      along_line(hold, pose, 2.0, -s.start_out_m, back);
      along_line(hold, pose, 2.0, back, -s.start_out_m);
    }
    hardware::ScriptedTrajectory& r = run.right;
    hardware::Keyframe last = r.keyframes.back();
    last.time_s = std::max(last.time_s, time_limit_s) + 1.0;
    r.keyframes.push_back(last);
    return last.time_s;
  }

  // The held tip eased from tip0 to tip1 and its direction from dir0 to dir1.
  void carry(const HeldCatheter& hold, Pose* pose, double duration, const V& tip0, const V& tip1,
             const V& dir0, const V& dir1) {
    const int n = steps(duration);
    const double t0 = run.right.keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double e = smoothstep(static_cast<double>(k) / n);
      const V dir = ((1.0 - e) * dir0 + e * dir1).normalized();
      *pose = solve_pose(right, hold, tip0 + e * (tip1 - tip0), dir, pose->hinge);
      key(&run.right, right, t0 + duration * k / n, pose->hinge, pose->roll_x, s.grip_closed_rad);
    }
  }

  // The held tip from s0 to s1 along the line the pose achieves through the incision's centre.
  void along_line(const HeldCatheter& hold, Pose* pose, double duration, double s0, double s1) {
    const int n = steps(duration);
    const double t0 = run.right.keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double along = s0 + (s1 - s0) * smoothstep(static_cast<double>(k) / n);
      V dir = g.in_dir;
      for (int it = 0; it < 4; ++it) {
        *pose = solve_pose(right, hold, g.incision + along * dir, g.in_dir, pose->hinge);
        dir = pose->achieved_dir;
      }
      run.worst_direction_error_deg = std::max(run.worst_direction_error_deg, pose->error_deg);
      key(&run.right, right, t0 + duration * k / n, pose->hinge, pose->roll_x, s.grip_closed_rad);
    }
  }

  // The left hand: into view on its port's line to the incision, at the first place clear of
  // every organ by 8 mm (its hinge and its jaws' tips) and seen by the laparoscope; waits there.
  void waiting_hand(const SessionModel& model, double end_s) {
    const std::vector<const haptics::MeshDatabase*> organs = model.rest_databases();
    const TaskModel& task = model.task();
    auto clear_and_seen = [&](const V& hinge, const V& jaw_tip) {
      for (const haptics::MeshDatabase* db : organs) {
        for (const V& x : {hinge, jaw_tip}) {
          V q;
          if (db->nearest_face(x, &q, nullptr) >= 0 && (q - x).norm() < 0.008) return false;
        }
      }
      const V to = (hinge - task.picture.camera_W).normalized();
      return to.dot(task.picture.view_dir_W) > task.picture.cos_half_view;
    };
    const V to_port = (left.port_W - g.incision).normalized();
    V park = g.incision + 0.06 * to_port;
    for (double d = 0.03; d <= 0.12; d += 0.005) {
      const V h = g.incision + d * to_port;
      if (clear_and_seen(h, h - 0.02 * to_port)) {
        park = h;
        break;
      }
    }
    hardware::ScriptedTrajectory& l = run.left;
    const V entry = left.port_W - 0.05 * to_port;
    const V x = to_port.unitOrthogonal();
    key(&l, left, 0.0, entry, x, s.grip_open_rad);
    move(&l, left, 1.5, entry, park, x, x, s.grip_open_rad, s.grip_open_rad);
    key(&l, left, end_s, park, x, s.grip_open_rad);
  }

  // How far along the left jaws, from the hinge, the duct's axis lies when they steady it.
  [[nodiscard]] double steady_depth_m() const { return s.steady_depth * 2.0 * g.jaw_mid_m; }

  // Whether the left tool, its hinge at `hinge` on its port's line, keeps its shaft (port to
  // hinge) `shaft_margin` and its closed jaws (hinge to their tips) `jaw_margin` from every
  // organ but the duct (sampled every 1 mm).
  [[nodiscard]] bool left_clear(const SessionModel& model, const V& hinge) const {
    const std::vector<const haptics::MeshDatabase*> organs = model.rest_databases();
    const int32_t duct = model.tissue().duct_organ();
    const V u = (hinge - left.port_W).normalized();
    const double shaft = (hinge - left.port_W).norm();
    const double tips = shaft + 2.0 * g.jaw_mid_m;
    for (size_t o = 0; o < organs.size(); ++o) {
      if (static_cast<int32_t>(o) == duct) continue;
      for (double d = 0.0; d <= tips; d += 0.001) {
        const V x = left.port_W + d * u;
        const double margin = d <= shaft ? s.steady_clearance_m : s.steady_jaw_clearance_m;
        V q;
        if (organs[o]->nearest_face(x, &q, nullptr) >= 0 && (q - x).norm() < margin) return false;
      }
    }
    return true;
  }

  // Where the left hand takes the duct: the point of its axis (duct frame) the jaws' middle
  // goes to, jaws across the duct (so that they bite a jaw's width along it), its shaft and
  // jaws clear of the other organs. Preferred beyond where the catheter's tip stops, on the
  // line it comes along (the side towards the common bile duct); then further on, then behind
  // the incision (towards the gallbladder's neck, where in the stand-in scene (then the default)
  // and the easy patient the jaws pressed the gallbladder with 9-22 N), 1 mm at a time. Nothing
  // when none fits.
  [[nodiscard]] std::optional<double> steady_site(const SessionModel& model) const {
    const models::IncisionRim& rim = *g.rim;
    const double forward = rim.z_m < 0.5 * rim.length_m ? 1.0 : -1.0;  // along g.axis
    const double bite = model.tissue().settings().duct_grasp.jaw_half_width_m;
    const double depth = model.task().spec.insertion_depth_m;
    auto usable = [&](double z) {
      if (z - bite < 0.0 || z + bite > rim.length_m) return false;
      const V hinge = hinge_holding(left, g.pose_WD * V(0.0, 0.0, z), steady_depth_m());
      return left_clear(model, hinge);
    };
    const double beyond = rim.z_m + forward * (rim.half_length_m + s.steady_gap_m + bite);
    (void)depth;
    for (double z = beyond; z >= 0.0 && z <= rim.length_m; z += forward * 0.001) {
      if (usable(z)) return z;
    }
    const double behind = rim.z_m - forward * (rim.half_length_m + s.steady_gap_m + bite);
    for (double z = behind; z >= 0.0 && z <= rim.length_m; z -= forward * 0.001) {
      if (usable(z)) return z;
    }
    return std::nullopt;
  }

  // The left hand: into view, over the duct beside the incision with its jaws open across it,
  // down onto it, closed just past the grasp angle; holds it there to the end. Where there is
  // no room beside the incision, it waits in view instead (waiting_hand).
  void steadying_hand(const SessionModel& model, double end_s) {
    const std::optional<double> site = steady_site(model);
    if (!site) {
      waiting_hand(model, end_s);
      return;
    }
    run.steady_site_m = *site;
    const V on_axis = g.pose_WD * V(0.0, 0.0, *site);
    const V hinge = hinge_holding(left, on_axis, steady_depth_m());
    const V x = left.shaft_dir(hinge).cross(g.axis).normalized();
    const V over = hinge + 0.02 * left.shaft_dir(hinge);
    const V entry = left.port_W + 0.05 * (over - left.port_W).normalized();
    const double open = s.grip_open_rad;
    hardware::ScriptedTrajectory& l = run.left;
    key(&l, left, 0.0, entry, x, open);
    move(&l, left, 1.5, entry, over, x, x, open, open);
    move(&l, left, 1.0, over, hinge, x, x, open, open);
    move(&l, left, 1.0, hinge, hinge, x, x, open, s.steady_grip_rad);
    key(&l, left, std::max(end_s, l.keyframes.back().time_s), hinge, x, s.steady_grip_rad);
  }

  // The clumsy right hand that takes the duct beside the incision instead of the catheter
  // (across its jaws, at mid-jaw), shuts them and pulls it 3 cm towards its port.
  void duct_tearing_hand(double end_s) {
    const models::IncisionRim& rim = *g.rim;
    hardware::ScriptedTrajectory& r = run.right;
    r.keyframes.clear();
    const double side = rim.z_m < 0.5 * rim.length_m ? 1.0 : -1.0;
    const V on_axis = g.pose_WD * V(0.0, 0.0, rim.z_m + side * (rim.half_length_m + 0.004));
    const V hinge = hinge_holding(right, on_axis, g.jaw_mid_m);
    const V x = right.shaft_dir(hinge).cross(g.axis).normalized();
    const V over = hinge + 0.02 * right.shaft_dir(hinge);
    const V pulled = hinge + 0.03 * right.shaft_dir(hinge);
    const double open = s.grip_open_rad;
    key(&r, right, 0.0, right_entry(over), x, open);
    move(&r, right, 1.5, right_entry(over), over, x, x, open, open);
    move(&r, right, 1.0, over, hinge, x, x, open, open);
    move(&r, right, 0.5, hinge, hinge, x, x, open, 0.0);
    move(&r, right, 1.0, hinge, pulled, x, x, 0.0, 0.0);
    key(&r, right, end_s, pulled, x, 0.0);
  }
};

}  // namespace

ExpertRunSettings expert_run_settings(const Scenario& scenario) {
  ExpertRunSettings s;
  if (scenario.task && scenario.task->expert_entry_slant_deg) {
    s.entry_slant_deg = *scenario.task->expert_entry_slant_deg;
  }
  return s;
}

Result<ExpertRun> plan_expert_run(const Scene& scene, const SessionModel& model,
                                  const ExpertRunSettings& settings) {
  const Scenario& sc = scene.scenario;
  auto problem = [&](const std::string& what) {
    return Result<ExpertRun>(std::vector<Diagnostic>{{sc.file.string(), 0, "task", what}});
  };
  if (!sc.task || sc.task->kind != "catheter-insertion" || !sc.catheter) {
    return problem("the expert run is planned for a catheter-insertion task with a catheter");
  }
  if (!model.tissue().duct().has_incision) return problem("the target duct has no incision");
  const Geometry g = measure(model, settings);
  if (settings.mistake == ExpertMistake::kEntersCommonBileDuct && model.task().cbd_organ < 0) {
    return problem("the clumsy run into the common bile duct needs task.common_bile_duct");
  }
  Planner p{settings, g, {}, {}, {}, model.task().spec.time_limit_s};
  if (model.task().cbd_organ >= 0) {
    const std::vector<const haptics::MeshDatabase*> dbs = model.rest_databases();
    p.cbd_surface = dbs[static_cast<size_t>(model.task().cbd_organ)];
    p.duct_surface = dbs[static_cast<size_t>(model.tissue().duct_organ())];
    p.camera_W = model.task().picture.camera_W;
  }
  for (size_t side : {size_t{0}, size_t{1}}) {
    PortTool& tool = side == 0 ? p.left : p.right;
    tool.port_W = model.tool(side).trocar.port_W;
    tool.shaft_length_m = model.tool(side).trocar.shaft_length_m;
  }
  const double end_s = p.catheter_hand();
  p.steadying_hand(model, end_s);
  if (settings.mistake == ExpertMistake::kTearsDuct) {
    p.duct_tearing_hand(end_s);  // keyed afresh: its poses are the last ones, holding no catheter
    p.right_poses.erase(p.right_poses.begin(),
                        p.right_poses.end() - static_cast<ptrdiff_t>(p.run.right.keyframes.size()));
    p.holding_from = SIZE_MAX;
  }
  p.run.right_shaft.radius_m = 0.0025;  // the scenario's default (ToolSpec)
  for (const ToolSpec& t : sc.tools) {
    if (t.side == ToolSpec::Side::kRight) p.run.right_shaft.radius_m = t.shaft_radius_m;
  }
  p.run.held_catheter.radius_m = 0.5 * sc.catheter->diameter_m;
  p.measure_right_clearances(model);
  return std::move(p.run);
}

Status save_trajectory_csv(const hardware::ScriptedTrajectory& trajectory,
                           const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) return Status(Diagnostic{file.string(), 0, "", "cannot be written"});
  out << "time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad\n";
  out.precision(9);
  for (const hardware::Keyframe& k : trajectory.keyframes) {
    const Eigen::Quaterniond& q = k.orientation_W;
    out << k.time_s << ',' << k.position_W.x() << ',' << k.position_W.y() << ',' << k.position_W.z()
        << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ','
        << k.gripper_angle_rad << '\n';
  }
  out.close();
  if (!out) return Status(Diagnostic{file.string(), 0, "", "could not be written completely"});
  return {};
}

}  // namespace lap::sim
