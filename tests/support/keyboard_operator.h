#pragma once
/// \file
/// A resident at the keyboard, for tests: an operator who watches the expert's run (a scenario's
/// shipped expert scripts) and copies it with the keys the application gives, one key at a time,
/// at a held key's autorepeat rate or slower, on the active tool only (T switches tools, and takes
/// a press's time), each press doing what it does in the window (hardware::key_nudge and
/// hardware::nudged, as app::LiveSession applies them). Coarse presses while the hand is far from
/// the expert's, Shift's quarter presses to land. The operator looks at the expert, not at the
/// simulation: where the keys cannot follow the expert's hand it falls behind and catches up, so
/// its presses are planned ahead (plan()); whoever plays them stops pressing while the heads-up
/// display says hold (tests/sim/keyboard_run_test.cpp in --fast, tests/app/session_flow_test.cpp
/// in the window, in real time). The same operator with the 3D mouse (PuckOperator) and with the
/// mouse alone (MouseOperator) follows the run the same way (follow_expert).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hardware/mouse_nudge.h"
#include "hardware/scripted_trajectory.h"
#include "hardware/simulated_device.h"
#include "hardware/space_mouse.h"
#include "hardware/tool_nudge.h"
#include "sim/runtime/trocar_tool.h"
#include "sim/setup/camera_picture.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"
#include "tests/test_support.h"

namespace lap::test {

struct Press {
  double t_s = 0.0;
  int tool = 0;
  hardware::ToolKey key = hardware::ToolKey::kXPlus;
  bool fine = false;  ///< Shift held: a quarter step
};

/// A nudge at a time: a key press (hardware::key_nudge) or a frame's motion of the 3D mouse.
struct TimedNudge {
  double t_s = 0.0;
  int tool = 0;
  hardware::ToolNudge nudge;
};

/// A press as the nudge it makes.
inline TimedNudge as_nudge(const Press& p) {
  return {p.t_s, p.tool, hardware::key_nudge(p.key, p.fine)};
}

struct KeyChoice {
  hardware::ToolKey key = hardware::ToolKey::kXPlus;
  bool fine = false;
};

// The keys an operator presses to follow `expert` from `start`: every 1/presses_per_s s one
// press, of the key that most reduces the active tool's largest error to the expert's pose at
// the operator's place in the script (position along one axis in steps, the jaws' opening, the
// roll of the jaws' opening direction about the shaft); when the active tool is within half a
// fine (Shift) step of the expert on all of them and the other is not, a switch to the other (no
// key pressed on a tool); when both are, the operator reads on in the script by one press's time.
struct KeyboardOperator {
  std::array<hardware::ScriptedTrajectory, 2> expert;
  std::array<hardware::SimulatedInput, 2> start;
  std::array<Eigen::Vector3d, 2> ports_W;
  std::array<Eigen::AlignedBox3d, 2> workspaces_W;
  /// The laparoscope's picture at the scenario's camera: the mouse drags in its plane.
  sim::CameraPicture picture;
  double presses_per_s = 20.0;
  double give_up_s = 300.0;
  /// Where the operator starts reading the expert's run: once the expert has brought both
  /// instruments into the laparoscope's picture (its approach through the ports is not followed:
  /// the keyboard's tools start in view, sim::home_handle_position).
  double script_start_s = 0.0;

  struct Plan {
    std::vector<Press> presses;
    int switches = 0;
    double script_done_s = 0.0;  ///< when the operator reached the expert's last keyframe
  };

  // The jaws' opening direction (the device's x axis made perpendicular to the shaft,
  // sim::tool_kinematics) of orientation q with the handle at p.
  Eigen::Vector3d opening_dir(int tool, const Eigen::Quaterniond& q,
                              const Eigen::Vector3d& p) const {
    const Eigen::Vector3d s = (ports_W[static_cast<size_t>(tool)] - p).normalized();
    const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
    return (x - x.dot(s) * s).normalized();
  }

  // The roll about the shaft (towards the port, from the handle at `at`) that turns at's jaws'
  // opening direction to want's [rad, -pi..pi].
  [[nodiscard]] double roll_error(int tool, const hardware::SimulatedInput& at,
                                  const hardware::DeviceSample& want) const {
    const Eigen::Vector3d s = (ports_W[static_cast<size_t>(tool)] - at.position_W).normalized();
    const Eigen::Vector3d now = opening_dir(tool, at.orientation_W, at.position_W);
    const Eigen::Vector3d goal = opening_dir(tool, want.orientation_W, at.position_W);
    return std::atan2(now.cross(goal).dot(s), now.dot(goal));
  }

  // The press that most reduces tool's largest error, measured in fine presses (Shift: a
  // quarter step); a whole press while that error is at least three quarters of one. None
  // within half a fine press.
  std::optional<KeyChoice> best_key(int tool, const hardware::SimulatedInput& at,
                                    const hardware::DeviceSample& want) const {
    constexpr double kFine = hardware::kKeyFineFraction;
    double worst = 0.5 + 1e-6;  // in fine presses
    std::optional<hardware::ToolKey> key;
    const Eigen::Vector3d e = want.position_W - at.position_W;
    constexpr std::array<std::array<hardware::ToolKey, 2>, 3> kAxis{
        {{hardware::ToolKey::kXMinus, hardware::ToolKey::kXPlus},
         {hardware::ToolKey::kYMinus, hardware::ToolKey::kYPlus},
         {hardware::ToolKey::kZMinus, hardware::ToolKey::kZPlus}}};
    for (int a = 0; a < 3; ++a) {
      const double presses = std::abs(e[a]) / (kFine * hardware::kKeyStepM);
      if (presses > worst) {
        worst = presses;
        key = kAxis[static_cast<size_t>(a)][e[a] > 0.0 ? 1 : 0];
      }
    }
    const double open = want.gripper_angle_rad - at.gripper_angle_rad;
    if (std::abs(open) / (kFine * hardware::kKeyOpeningRad) > worst) {
      worst = std::abs(open) / (kFine * hardware::kKeyOpeningRad);
      key = open > 0.0 ? hardware::ToolKey::kOpen : hardware::ToolKey::kClose;
    }
    const double roll = roll_error(tool, at, want);
    if (std::abs(roll) / (kFine * hardware::kKeyRollRad) > worst) {
      worst = std::abs(roll) / (kFine * hardware::kKeyRollRad);
      key = roll > 0.0 ? hardware::ToolKey::kRollPlus : hardware::ToolKey::kRollMinus;
    }
    if (!key) return std::nullopt;
    return KeyChoice{*key, worst < 0.75 / kFine};
  }

  [[nodiscard]] Plan plan() const;  // below follow_expert
};

/// What an operator does: its motions (key presses, or nudges of the 3D mouse or the mouse), T
/// presses, and when it had followed the expert's run to its end.
template <typename M>
struct Followed {
  struct Timed {
    double t_s = 0.0;
    int tool = 0;
    M motion;
  };
  std::vector<Timed> motions;
  int switches = 0;
  double script_done_s = 0.0;
};

/// The expert's run followed every `period` s by a motion of the active tool: `motion(tool, at,
/// want)` (an optional M: none once `at` is settled on `want`), applied as `as_nudge(M)`. When the
/// active tool is settled and the other is not, a switch to the other (T: no motion made); when
/// both are, the operator reads on in the script by one period.
template <typename M, typename Motion, typename AsNudge>
Followed<M> follow_expert(const KeyboardOperator& op, double period, Motion motion,
                          AsNudge as_nudge) {
  Followed<M> out;
  if (op.expert[0].keyframes.empty() || op.expert[1].keyframes.empty()) return out;  // not loaded
  std::array<hardware::SimulatedInput, 2> at = op.start;
  const double end = std::max(op.expert[0].duration_s(), op.expert[1].duration_s());
  double script_s = op.script_start_s;
  int active = 1;  // the window starts with the right tool active
  std::array<size_t, 2> cursor{};
  for (double t = period; t < op.give_up_s; t += period) {
    std::array<std::optional<M>, 2> m;
    for (int tool = 0; tool < 2; ++tool) {
      const auto i = static_cast<size_t>(tool);
      hardware::DeviceSample want;
      op.expert[i].sample(script_s, &cursor[i], &want);
      m[i] = motion(tool, at[i], want);
    }
    const auto a = static_cast<size_t>(active);
    if (m[a]) {
      at[a] = hardware::nudged(at[a], as_nudge(*m[a]), op.workspaces_W[a], op.ports_W[a]);
      out.motions.push_back({t, active, *m[a]});
    } else if (m[1 - a]) {
      active = 1 - active;
      ++out.switches;
    } else if (script_s < end) {
      script_s = std::min(end, script_s + period);
      if (script_s == end) out.script_done_s = t;
    } else {
      break;  // done: both tools hold the expert's last pose
    }
  }
  return out;
}

inline KeyboardOperator::Plan KeyboardOperator::plan() const {
  const Followed<KeyChoice> f = follow_expert<KeyChoice>(
      *this, 1.0 / presses_per_s,
      [this](int tool, const hardware::SimulatedInput& at, const hardware::DeviceSample& want) {
        return best_key(tool, at, want);
      },
      [](const KeyChoice& k) { return hardware::key_nudge(k.key, k.fine); });
  Plan out;
  for (const auto& m : f.motions)
    out.presses.push_back({m.t_s, m.tool, m.motion.key, m.motion.fine});
  out.switches = f.switches;
  out.script_done_s = f.script_done_s;
  return out;
}

/// A continuous operator's plan: a nudge a frame.
using FollowPlan = Followed<hardware::ToolNudge>;
inline hardware::ToolNudge as_is(const hardware::ToolNudge& n) { return n; }
inline std::vector<TimedNudge> timed_nudges(const FollowPlan& plan) {
  std::vector<TimedNudge> out;
  out.reserve(plan.motions.size());
  for (const auto& m : plan.motions) out.push_back({m.t_s, m.tool, m.motion});
  return out;
}

/// The same operator with a 3D mouse: every frame of the window's graphics loop (which polls the
/// puck) it deflects the puck towards the expert's pose of the active tool, all three axes at
/// once, so that the handle would close the error in kReachS (no faster than the puck's full
/// speed); twists it the same way for the roll; holds a button for the jaws. The puck's state
/// goes through hardware::space_mouse_nudge with `mapping`, as app::OperativeView does, and its
/// raw counts are whole numbers, as spacenavd's. T switches tools, as with the keys.
struct PuckOperator {
  const KeyboardOperator* op = nullptr;
  hardware::SpaceMouseMapping mapping;
  double frame_hz = 60.0;
  static constexpr double kReachS = 0.15;
  static constexpr double kSettledM = 2e-4;
  static constexpr double kSettledRollRad = 0.01;
  static constexpr double kSettledJawsRad = 0.01;

  // Raw counts for a wanted rate: the inverse of space_mouse_nudge's dead zone and scale.
  [[nodiscard]] int counts(double rate, double full_rate) const {
    const double share = std::min(1.0, std::abs(rate) / full_rate);
    if (share < 1e-3) return 0;
    const double u = mapping.dead_zone + (1.0 - mapping.dead_zone) * share;
    return static_cast<int>(std::copysign(std::round(u * mapping.full_scale), rate));
  }

  // The puck's state that moves `at` towards `want`; none once settled.
  [[nodiscard]] std::optional<hardware::SpaceMouseState> puck(
      int tool, const hardware::SimulatedInput& at, const hardware::DeviceSample& want) const {
    const Eigen::Vector3d e = want.position_W - at.position_W;
    const double roll = op->roll_error(tool, at, want);
    const double jaws = want.gripper_angle_rad - at.gripper_angle_rad;
    const double frame_jaws = mapping.jaw_rate_rad_per_s / frame_hz;
    if (e.norm() < kSettledM && std::abs(roll) < kSettledRollRad &&
        std::abs(jaws) < std::max(kSettledJawsRad, 0.5 * frame_jaws)) {
      return std::nullopt;
    }
    hardware::SpaceMouseState p;
    for (int a = 0; a < 3; ++a) {
      p.axes[static_cast<size_t>(a)] =
          counts(mapping.axis_sign[a] * e[a] / kReachS, mapping.speed_m_per_s);
    }
    p.axes[5] = counts(mapping.roll_sign * roll / kReachS, mapping.roll_rate_rad_per_s);
    if (std::abs(jaws) >= 0.5 * frame_jaws) p.buttons = jaws < 0.0 ? 1U : 2U;
    return p;
  }

  [[nodiscard]] FollowPlan plan() const {
    const double period = 1.0 / frame_hz;
    return follow_expert<hardware::ToolNudge>(
        *op, period,
        [&](int tool, const hardware::SimulatedInput& at, const hardware::DeviceSample& want) {
          const std::optional<hardware::SpaceMouseState> p = puck(tool, at, want);
          return p ? std::optional(hardware::space_mouse_nudge(*p, mapping, period)) : std::nullopt;
        },
        as_is);
  }
};

/// The same operator with the mouse alone, Ctrl held (app/vtk_view.cpp, through
/// hardware::mouse_*_nudge): every frame of the window's graphics loop one gesture, whole pixels
/// and wheel notches, of what is furthest from the expert's pose of the active tool: a left drag
/// in the picture's plane (at most kMaxPixels a frame along each of its axes), a notch of the
/// wheel along the line of sight (with Shift a quarter notch when within three quarters of a
/// notch), a middle drag for the roll, a right drag for the jaws. T switches tools, as with the
/// keys. The picture's plane is the scenario's camera's (the resident does not move the scope).
struct MouseOperator {
  const KeyboardOperator* op = nullptr;
  double frame_hz = 60.0;
  static constexpr double kMaxPixels = 12.0;  ///< 720 pixels a second: a brisk stroke

  // The gesture for `at` towards `want`, if anything is more than half its smallest motion
  // away; each error is measured in those smallest motions (a pixel, a quarter notch).
  [[nodiscard]] std::optional<hardware::ToolNudge> gesture(
      int tool, const hardware::SimulatedInput& at, const hardware::DeviceSample& want) const {
    const sim::CameraPicture& v = op->picture;
    const Eigen::Vector3d e = want.position_W - at.position_W;
    const double px_x = e.dot(v.view_right_W) / hardware::kMouseMetresPerPixel;
    const double px_y = -e.dot(v.view_up_W) / hardware::kMouseMetresPerPixel;  // screen y down
    constexpr double kFineNotch = hardware::kKeyFineFraction;
    const double notches = e.dot(v.view_dir_W) / hardware::kMouseWheelMetresPerNotch;
    const double roll_px = op->roll_error(tool, at, want) / hardware::kMouseRollRadPerPixel;
    const double jaws_px =
        -(want.gripper_angle_rad - at.gripper_angle_rad) / hardware::kMouseJawsRadPerPixel;
    const double plane = std::max(std::abs(px_x), std::abs(px_y));
    const double depth = std::abs(notches) / kFineNotch;
    const double worst = std::max({plane, depth, std::abs(roll_px), std::abs(jaws_px)});
    if (worst < 0.5) return std::nullopt;
    auto pixels = [](double want_px) {
      return std::clamp(std::round(want_px), -kMaxPixels, kMaxPixels);
    };
    if (worst == plane) {
      return hardware::mouse_drag_nudge(pixels(px_x), pixels(px_y), v.view_right_W, v.view_up_W);
    }
    if (worst == depth) {
      const bool fine = std::abs(notches) < 0.75;
      return hardware::mouse_wheel_nudge(std::copysign(1.0, notches), v.view_dir_W, fine);
    }
    if (worst == std::abs(roll_px)) return hardware::mouse_roll_nudge(pixels(roll_px));
    return hardware::mouse_jaws_nudge(pixels(jaws_px));
  }

  [[nodiscard]] FollowPlan plan() const {
    return follow_expert<hardware::ToolNudge>(
        *op, 1.0 / frame_hz,
        [&](int tool, const hardware::SimulatedInput& at, const hardware::DeviceSample& want) {
          return gesture(tool, at, want);
        },
        as_is);
  }
};

/// The operator for the shipped expert scripts scenarios/scripts/`stem`/expert_*.csv on `scene`,
/// from the keyboard's home pose of each tool (app::LiveSession: sim::home_handle_position, the
/// jaws half open, the orientation the identity), starting where the expert has both
/// instruments in the laparoscope's picture.
inline KeyboardOperator keyboard_operator(const sim::Scene& scene, const std::string& stem,
                                          double presses_per_s) {
  KeyboardOperator op;
  op.presses_per_s = presses_per_s;
  const hardware::SimulatedDevice probe({}, "limits");
  for (int side = 0; side < 2; ++side) {
    const auto i = static_cast<size_t>(side);
    const std::filesystem::path script = source_dir() / "scenarios/scripts" / stem /
                                         (side == 0 ? "expert_left.csv" : "expert_right.csv");
    auto t = hardware::load_scripted_trajectory(script);
    if (!t.ok()) {
      ADD_FAILURE() << t.message();
      return op;
    }
    op.expert[i] = std::move(t).value();
    op.start[i].position_W = sim::home_handle_position(scene, side);
    op.start[i].gripper_angle_rad = 0.6;
    const sim::ToolSpec* tool =
        scene.scenario.tool(side == 0 ? sim::ToolSpec::Side::kLeft : sim::ToolSpec::Side::kRight);
    EXPECT_NE(tool, nullptr);
    op.ports_W[i] = scene.scenario.trocar(tool->trocar)->position_m;
    op.workspaces_W[i] = probe.limits().workspace_W;
  }
  op.picture = sim::CameraPicture::of(scene.scenario.camera);
  sim::RuntimeSettings rs;
  rs.fast = true;
  const auto model =
      sim::SessionModel::build(scene, rs, {sim::DeviceDescription{"left", {}}, {"right", {}}});
  EXPECT_TRUE(model.ok()) << model.message();
  const sim::SessionModel& m = *model.value();
  for (size_t i = 0; i < 2; ++i) EXPECT_EQ(op.ports_W[i], m.tool(i).trocar.port_W);
  // The first 10 ms at which both of the expert's jaws' hinges are in the picture.
  std::array<size_t, 2> cursor{};
  for (double t = 0.0; t <= op.expert[1].duration_s(); t += 0.01) {
    bool both = true;
    for (size_t i = 0; i < 2; ++i) {
      hardware::DeviceSample at;
      op.expert[i].sample(t, &cursor[i], &at);
      const sim::ToolKinematics k =
          sim::tool_kinematics(m.tool(i).trocar, at, m.tool(i).initial_axis_W);
      both = both && m.task().in_view(k.pose.hinge_W);
    }
    if (both) {
      op.script_start_s = t;
      break;
    }
  }
  return op;
}

}  // namespace lap::test
