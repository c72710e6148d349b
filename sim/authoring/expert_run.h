#pragma once
/// \file
/// The expert's run of the catheter insertion (thesis §7.4, Figures 7-18 to 7-23), planned from
/// a scenario's geometry as keyframe scripts for the two hands (hardware/scripted_trajectory.h):
/// the right hand grasps the catheter a little behind its tip with the jaws across it, carries
/// the tip in front of the incision pointing into the lumen at a slant towards the duct's far
/// end, and pushes it in along that line until the target depth is passed, then holds still;
/// meanwhile the left hand takes the duct beside the incision, its jaws across it and closed
/// just enough to hold it (gently: below the task's squeeze and force thresholds), and steadies
/// it there while the catheter goes in. Written by
/// `laptrainer-cli plan-expert`; the scripts shipped in scenarios/scripts/<stem>/ come from it,
/// and a test runs them to success.
///
/// How the jaws hold the catheter fixes where its tip is in the jaws' frame: the plan keeps that
/// (the held section is rigid in the jaws, models/catheter_grasp.h) and solves, for each
/// keyframe, the tool's pose — the hinge through the port's fulcrum and the roll about the shaft
/// (sim/runtime/trocar_tool.h) — that puts the tip on the wanted line with the catheter as near
/// the wanted direction as the fulcrum lets it point. On the way in, the line is the one the
/// pose achieves through the incision's centre, so the held catheter stays on a line through the
/// hole while it advances.

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <string_view>

#include "core/result.h"
#include "hardware/scripted_trajectory.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"

namespace lap::sim {

/// What a clumsy run gets wrong, each failing the task for its own reason: the right hand
/// opens its jaws on the way to the incision and leaves the catheter lying (catheter_dropped);
/// it pushes on 2 cm past where the expert stops, and the tip goes through the duct's wall
/// (wall_perforation); instead of taking the catheter it takes the duct beside the incision and
/// pulls it 3 cm towards its port (duct_injury: the grasp's pull on the duct); it takes the
/// common bile duct beside the cystic duct for it and pushes the catheter in through its wall
/// (common_bile_duct: the scenario's task names that organ); or it carries the
/// catheter to the incision and hesitates there, never putting it in, until the scenario's time
/// limit has passed (time_limit).
/// Pushing the duct is not among them: a soft tube held only at its ends (20–60 N/m to a push
/// at its middle) moves away long before the 2 N threshold, and the jaws' squeeze on it stays
/// under 0.5 N shut (models/duct_grasp.h).
enum class ExpertMistake {
  kNone,
  kDropsCatheter,
  kOvershoots,
  kTearsDuct,
  kEntersCommonBileDuct,
  kHesitates,
};
/// The mistake's name on the command line (`plan-expert --mistake NAME`) and in its scripts'
/// names (clumsy_NAME_left.csv): "drop", "overshoot", "tear", "cbd", "time_limit"; "" for kNone.
[[nodiscard]] std::string_view to_string(ExpertMistake mistake);
/// The mistake named so, if any (kNone is not named).
[[nodiscard]] std::optional<ExpertMistake> parse_mistake(std::string_view name);
/// Every clumsy run, in the order above.
inline constexpr std::array<ExpertMistake, 5> kClumsyRuns = {
    ExpertMistake::kDropsCatheter, ExpertMistake::kOvershoots, ExpertMistake::kTearsDuct,
    ExpertMistake::kEntersCommonBileDuct, ExpertMistake::kHesitates};

struct ExpertRunSettings {
  ExpertMistake mistake = ExpertMistake::kNone;
  /// The catheter's slant to the duct's axis as it enters, into the wall [deg]: shallow enough
  /// to turn along the lumen, steep enough to pass the hole (the catheter is 1.7 mm across, the
  /// lumen 3 mm). A scenario may name its own (task.expert_entry_slant_deg:
  /// expert_run_settings): the fulcrum meets some slants better than others.
  double entry_slant_deg = 39.0;
  double grasp_from_tip_m = 0.025;  ///< where the jaws take the catheter, behind its tip
  double grasp_depth = 0.5;         ///< how far along the jaws it lies, from the hinge (of 1)
  double start_out_m = 0.010;       ///< the tip's start in front of the incision, along the line
  /// How far the line is pushed past the incision: the target depth and what the catheter's
  /// bend in the lumen and the grasp's virtual coupling (its give F / k under the lumen's
  /// friction, models/catheter_grasp.h) take up. 27 mm before the grasp was a virtual
  /// coupling: with it, 3 of the stand-in scene's (then the default's) 12 varied expert runs then
  /// stopped at 9.86 mm; at 29 mm moderate's expert run goes out through the wall.
  double advance_m = 0.0275;
  double grip_open_rad = 0.8;
  double grip_closed_rad = 0.1;  ///< below the grasp angle (models/catheter_grasp.h)
  double keyframe_step_s = 0.1;
  double hold_after_s = 6.0;  ///< still at the end: the task's hold and some more
  /// The left hand steadies the duct beside the incision: its jaws across the duct, closed to
  /// this (just past the grasp angle of models/duct_grasp.h, 0.30 rad: the duct is taken but
  /// hardly squeezed), `steady_gap_m` from the incision's edge along the duct to the jaws'.
  double steady_grip_rad = 0.26;
  /// Where the duct lies along the jaws, from the hinge (of 1): towards their tips, which then
  /// reach only a few millimetres past it (the liver, the fat and the common bile duct lie
  /// close under it in the patients).
  double steady_depth = 0.75;
  double steady_gap_m = 0.0015;
  /// The left tool's shaft (its axis, port to hinge) stays this far from every organ but the
  /// duct: its radius, 2.5 mm, less 0.2 mm (it may graze a soft organ by as much: a few hundredths
  /// of a newton).
  double steady_clearance_m = 0.0023;
  /// Its closed jaws (the axis, hinge to their tips) this far: about their half-thickness,
  /// 1.5 mm, and 0.5 mm more (estimate).
  double steady_jaw_clearance_m = 0.002;
  /// The clumsy run into the common bile duct: how far past its wall the tip is pushed [m],
  /// and how far along it from its junction with the cystic duct (nearer, the cystic duct and
  /// the fat round the junction are in the way: at 6 and 10 mm the tip did not get in on every
  /// patient).
  double cbd_push_m = 0.015;
  double cbd_clear_m = 0.015;
};

/// How near the planned right hand comes to the organs it must not touch (every organ but the
/// target duct), over its keyframes (every 0.1 s): the least distance, from which organ, and
/// when. The planner does not steer round them; it measures, so that an author placing a new
/// patient's ports sees where the hand presses into an organ on its way.
struct PlannedClearance {
  /// The least distance from the axis to the organ's surface; negative where the axis is inside
  /// it, by that much (a ray from the point meets the surface first from behind) [m].
  double least_m = std::numeric_limits<double>::infinity();
  int32_t organ = -1;  ///< the scene's organ index, -1 where none was measured
  double time_s = 0.0;
  double radius_m = 0.0;  ///< of what was measured (its axis): nearer than this, it presses in
  /// How far it presses into that organ at the least distance [m] (0: clear).
  [[nodiscard]] double pressed_in_m() const { return std::max(0.0, radius_m - least_m); }
};

struct ExpertRun {
  hardware::ScriptedTrajectory left;
  hardware::ScriptedTrajectory right;
  /// The right tool's shaft (its axis, from the port to the hinge, every 1 mm; radius the
  /// scenario's shaft_radius_m).
  PlannedClearance right_shaft;
  /// The held catheter from where the jaws hold it to its tip (every 1 mm), from the grasp on
  /// (radius half the catheter's diameter_m; the duct, which it enters, is not measured).
  PlannedClearance held_catheter;
  /// The largest angle between the catheter's wanted and achieved directions on the way in
  /// (the fulcrum's limit) [deg].
  double worst_direction_error_deg = 0.0;
  /// Where the left hand steadies the duct: the jaws' middle along the duct's axis from its end
  /// [m] (the incision is at IncisionRim::z_m); empty where no line from the left tool's port
  /// reaches the duct beside the incision clear of the other organs, and it waits in view.
  std::optional<double> steady_site_m;
};

/// The planner's settings for `scenario`: the defaults above, with the approach its task names
/// (task.expert_entry_slant_deg).
[[nodiscard]] ExpertRunSettings expert_run_settings(const Scenario& scenario);

/// Fails, saying why, for a scenario without a catheter-insertion task, a catheter port or an
/// incision, and for the clumsy run into the common bile duct where the task names none.
/// `settings` has no default: the scenario's own (expert_run_settings) must not be skipped by
/// omission.
[[nodiscard]] Result<ExpertRun> plan_expert_run(const Scene& scene, const SessionModel& model,
                                                const ExpertRunSettings& settings);

/// The trajectory as a keyframe CSV (the format scripted_trajectory.h reads), to `file`.
[[nodiscard]] Status save_trajectory_csv(const hardware::ScriptedTrajectory& trajectory,
                                         const std::filesystem::path& file);

}  // namespace lap::sim
