#include "sim/authoring/expert_run.h"

#include <cmath>
#include <fstream>
#include <numbers>

namespace lap::sim {
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

struct Planner {
  const ExpertRunSettings& s;
  PortTool right;
  PortTool left;
  ExpertRun run;
  double t = 0.0;

  void key(hardware::ScriptedTrajectory* traj, const PortTool& tool, double time, const V& hinge,
           const V& roll_x, double grip) {
    traj->keyframes.push_back(tool.keyframe(time, hinge, roll_x, grip));
  }
  // The hinge, roll and grip eased from one to the other over `duration`.
  void move(hardware::ScriptedTrajectory* traj, const PortTool& tool, double duration, const V& h0,
            const V& h1, const V& x0, const V& x1, double g0, double g1) {
    const int n = std::max(1, static_cast<int>(std::lround(duration / s.keyframe_step_s)));
    const double t0 = traj->keyframes.empty() ? 0.0 : traj->keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double e = smoothstep(static_cast<double>(k) / n);
      const V x = ((1.0 - e) * x0 + e * x1).normalized();
      key(traj, tool, t0 + duration * k / n, h0 + e * (h1 - h0), x, g0 + e * (g1 - g0));
    }
  }
};

}  // namespace

Result<ExpertRun> plan_expert_run(const Scene& scene, const SessionModel& model,
                                  const ExpertRunSettings& settings) {
  const Scenario& sc = scene.scenario;
  auto problem = [&](const std::string& what) {
    return Result<ExpertRun>(std::vector<Diagnostic>{{sc.file.string(), 0, "task", what}});
  };
  if (!sc.task || sc.task->kind != "catheter-insertion" || !sc.catheter) {
    return problem("the expert run is planned for a catheter-insertion task with a catheter");
  }
  const DuctTissue& duct = model.tissue().duct();
  if (!duct.has_incision) return problem("the target duct has no incision");
  Planner p{settings, {}, {}, {}, 0.0};
  for (size_t side : {size_t{0}, size_t{1}}) {
    PortTool& tool = side == 0 ? p.left : p.right;
    tool.port_W = model.tool(side).trocar.port_W;
    tool.shaft_length_m = model.tool(side).trocar.shaft_length_m;
  }
  const double jaw_mid_m = 0.5 * model.tool(1).gripper.jaw_length_m;

  // The incision, the duct's axis towards its further end, and the line in.
  const models::IncisionRim& rim = duct.rim;
  const Eigen::Isometry3d pose_WD = rim.pose_DW.inverse();
  const V incision = pose_WD * V(rim.mid_radius_m * std::cos(rim.angle_rad),
                                 rim.mid_radius_m * std::sin(rim.angle_rad), rim.z_m);
  const V normal = pose_WD.linear() * V(std::cos(rim.angle_rad), std::sin(rim.angle_rad), 0.0);
  const V axis =
      (rim.z_m < 0.5 * rim.length_m ? 1.0 : -1.0) * (pose_WD.linear() * V::UnitZ()).normalized();
  const double slant = settings.entry_slant_deg * std::numbers::pi / 180.0;
  const V in_dir = (std::cos(slant) * axis - std::sin(slant) * normal).normalized();

  // The catheter as it lies, and the grasp a little behind its tip, jaws across it.
  const TissueWorldSettings& ws = model.tissue().settings();
  const V cath_dir = ws.catheter_direction_W.normalized();
  const V cath_tip = ws.catheter_start_W + ws.catheter.length_m * cath_dir;
  const V held = cath_tip - settings.grasp_from_tip_m * cath_dir;
  const V grasp_hinge = hinge_holding(p.right, held, settings.grasp_depth * 2.0 * jaw_mid_m);
  const V grasp_x = p.right.shaft_dir(grasp_hinge).cross(cath_dir).normalized();
  const Eigen::Matrix3d grasp_frame = p.right.frame(grasp_hinge, grasp_x);
  const HeldCatheter hold{grasp_frame.transpose() * (cath_tip - grasp_hinge),
                          grasp_frame.transpose() * cath_dir};

  // Right hand: in over the catheter with the jaws open, down onto it, close.
  hardware::ScriptedTrajectory& r = p.run.right;
  const V above = grasp_hinge + 0.02 * p.right.shaft_dir(grasp_hinge);
  const V entry = p.right.port_W + 0.05 * (above - p.right.port_W).normalized();
  const double open = settings.grip_open_rad;
  const double closed = settings.grip_closed_rad;
  p.key(&r, p.right, 0.0, entry, grasp_x, open);
  p.move(&r, p.right, 1.5, entry, above, grasp_x, grasp_x, open, open);
  p.move(&r, p.right, 1.0, above, grasp_hinge, grasp_x, grasp_x, open, open);
  p.move(&r, p.right, 0.5, grasp_hinge, grasp_hinge, grasp_x, grasp_x, open, closed);
  p.move(&r, p.right, 0.5, grasp_hinge, grasp_hinge, grasp_x, grasp_x, closed, closed);

  // Carry the tip round in front of the incision, then onto the line in; push along it.
  Pose pose{grasp_hinge, grasp_x, 0.0, cath_dir};
  auto carry = [&](double duration, const V& tip0, const V& tip1, const V& dir0, const V& dir1) {
    const int n = std::max(1, static_cast<int>(std::lround(duration / settings.keyframe_step_s)));
    const double t0 = r.keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double e = smoothstep(static_cast<double>(k) / n);
      const V dir = ((1.0 - e) * dir0 + e * dir1).normalized();
      pose = solve_pose(p.right, hold, tip0 + e * (tip1 - tip0), dir, pose.hinge);
      p.key(&r, p.right, t0 + duration * k / n, pose.hinge, pose.roll_x, closed);
    }
  };
  auto along_line = [&](double duration, double s0, double s1) {
    const int n = std::max(1, static_cast<int>(std::lround(duration / settings.keyframe_step_s)));
    const double t0 = r.keyframes.back().time_s;
    for (int k = 1; k <= n; ++k) {
      const double along = s0 + (s1 - s0) * smoothstep(static_cast<double>(k) / n);
      V dir = in_dir;
      for (int it = 0; it < 4; ++it) {  // the line the pose achieves, through the incision
        pose = solve_pose(p.right, hold, incision + along * dir, in_dir, pose.hinge);
        dir = pose.achieved_dir;
      }
      p.run.worst_direction_error_deg = std::max(p.run.worst_direction_error_deg, pose.error_deg);
      p.key(&r, p.right, t0 + duration * k / n, pose.hinge, pose.roll_x, closed);
    }
  };
  const V out_front = incision - 0.025 * in_dir + 0.01 * normal;
  const V start = incision - settings.start_out_m * in_dir;
  carry(2.5, cath_tip, out_front, cath_dir, in_dir);
  if (settings.mistake == ExpertMistake::kDropsCatheter) {
    // The jaws open on the way and stay open: from here on every keyframe lets go.
    const size_t from = r.keyframes.size() - 10;
    for (size_t k = from; k < r.keyframes.size(); ++k) {
      const double e = smoothstep(static_cast<double>(k - from + 1) / 10.0);
      r.keyframes[k].gripper_angle_rad = closed + e * (open - closed);
    }
  }
  carry(1.5, out_front, start, in_dir, in_dir);
  along_line(0.5, -settings.start_out_m, -settings.start_out_m);
  // The clumsy push goes on 2 cm past where the expert stops, as fast.
  const bool overshoot = settings.mistake == ExpertMistake::kOvershoots;
  const double advance = settings.advance_m + (overshoot ? 0.02 : 0.0);
  along_line(6.0 * advance / settings.advance_m, -settings.start_out_m,
             advance - settings.start_out_m);
  if (settings.mistake == ExpertMistake::kDropsCatheter) {
    for (size_t k = 0; k < r.keyframes.size(); ++k) {
      if (r.keyframes[k].time_s > 6.0) r.keyframes[k].gripper_angle_rad = open;
    }
  }
  const double end_s = r.keyframes.back().time_s + settings.hold_after_s;
  hardware::Keyframe last = r.keyframes.back();
  last.time_s = end_s;
  r.keyframes.push_back(last);

  // Left hand: into view on its port's line to the incision, clear of every organ.
  const std::vector<const haptics::MeshDatabase*> organs = model.rest_databases();
  const TaskModel& task = model.task();
  auto clear_and_seen = [&](const V& hinge, const V& jaw_tip) {
    for (const haptics::MeshDatabase* db : organs) {
      for (const V& x : {hinge, jaw_tip}) {
        V q;
        if (db->nearest_face(x, &q, nullptr) >= 0 && (q - x).norm() < 0.008) return false;
      }
    }
    const V to = (hinge - task.camera_W).normalized();
    return to.dot(task.view_dir_W) > task.cos_half_view;
  };
  const V to_port = (p.left.port_W - incision).normalized();
  V park = incision + 0.06 * to_port;
  for (double d = 0.03; d <= 0.12; d += 0.005) {
    const V h = incision + d * to_port;
    if (clear_and_seen(h, h - 0.02 * to_port)) {
      park = h;
      break;
    }
  }
  hardware::ScriptedTrajectory& l = p.run.left;
  const V left_entry = p.left.port_W - 0.05 * to_port;
  const V left_x = to_port.unitOrthogonal();
  p.key(&l, p.left, 0.0, left_entry, left_x, open);
  p.move(&l, p.left, 1.5, left_entry, park, left_x, left_x, open, open);
  p.key(&l, p.left, end_s, park, left_x, open);

  if (settings.mistake == ExpertMistake::kTearsDuct) {
    // The right hand, instead of taking the catheter, takes the duct beside the incision
    // between its jaws (across them, at mid-jaw), jaws shut, and pulls it 3 cm towards its
    // port.
    r.keyframes.clear();
    const V on_axis = pose_WD * V(0.0, 0.0,
                                  rim.z_m + (rim.z_m < 0.5 * rim.length_m ? 1 : -1) *
                                                (rim.half_length_m + 0.004));
    const V hinge = hinge_holding(p.right, on_axis, jaw_mid_m);
    const V x = p.right.shaft_dir(hinge).cross(axis).normalized();
    const V over = hinge + 0.02 * p.right.shaft_dir(hinge);
    p.key(&r, p.right, 0.0, entry, x, open);
    p.move(&r, p.right, 1.5, entry, over, x, x, open, open);
    p.move(&r, p.right, 1.0, over, hinge, x, x, open, open);
    p.move(&r, p.right, 0.5, hinge, hinge, x, x, open, 0.0);
    const V pulled = hinge + 0.03 * p.right.shaft_dir(hinge);
    p.move(&r, p.right, 1.0, hinge, pulled, x, x, 0.0, 0.0);
    p.key(&r, p.right, end_s, pulled, x, 0.0);
  }
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
