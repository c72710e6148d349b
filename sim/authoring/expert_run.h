#pragma once
/// \file
/// The expert's run of the catheter insertion (thesis §7.4, Figures 7-18 to 7-23), planned from
/// a scenario's geometry as keyframe scripts for the two hands (hardware/scripted_trajectory.h):
/// the right hand grasps the catheter a little behind its tip with the jaws across it, carries
/// the tip in front of the incision pointing into the lumen at a slant towards the duct's far
/// end, and pushes it in along that line until the target depth is passed, then holds still; the
/// left hand brings its tool into view clear of every organ and keeps it there. Written by
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

#include "core/result.h"
#include "hardware/scripted_trajectory.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"

namespace lap::sim {

/// What a clumsy run gets wrong, each failing the task for its own reason: the right hand
/// opens its jaws on the way to the incision and leaves the catheter lying (catheter_dropped);
/// it pushes on 2 cm past where the expert stops, and the tip goes through the duct's wall
/// (wall_perforation); instead of taking the catheter it takes the duct beside the incision and
/// pulls it 3 cm towards its port (duct_injury: the grasp's pull on the duct). The time limit's
/// clumsy run is the expert's own, too slow for a shorter limit (tests/sim/expert_run_test.cpp).
/// Pushing the duct is not among them: a soft tube held only at its ends (20–60 N/m to a push
/// at its middle) moves away long before the 2 N threshold, and the jaws' squeeze on it stays
/// under 0.5 N shut (models/duct_grasp.h).
enum class ExpertMistake { kNone, kDropsCatheter, kOvershoots, kTearsDuct };

struct ExpertRunSettings {
  ExpertMistake mistake = ExpertMistake::kNone;
  /// The catheter's slant to the duct's axis as it enters, into the wall [deg]: shallow enough
  /// to turn along the lumen, steep enough to pass the hole (the catheter is 1.7 mm across, the
  /// lumen 3 mm).
  double entry_slant_deg = 39.0;
  double grasp_from_tip_m = 0.025;  ///< where the jaws take the catheter, behind its tip
  double grasp_depth = 0.5;         ///< how far along the jaws it lies, from the hinge (of 1)
  double start_out_m = 0.010;       ///< the tip's start in front of the incision, along the line
  /// How far the line is pushed past the incision: the target depth and what the catheter's
  /// bend in the lumen takes up.
  double advance_m = 0.027;
  double grip_open_rad = 0.8;
  double grip_closed_rad = 0.1;  ///< below the grasp angle (models/catheter_grasp.h)
  double keyframe_step_s = 0.1;
  double hold_after_s = 6.0;  ///< still at the end: the task's hold and some more
};

struct ExpertRun {
  hardware::ScriptedTrajectory left;
  hardware::ScriptedTrajectory right;
  /// The largest angle between the catheter's wanted and achieved directions on the way in
  /// (the fulcrum's limit) [deg].
  double worst_direction_error_deg = 0.0;
};

/// Fails, saying why, for a scenario without a catheter-insertion task, a catheter port or an
/// incision.
[[nodiscard]] Result<ExpertRun> plan_expert_run(const Scene& scene, const SessionModel& model,
                                                const ExpertRunSettings& settings = {});

/// The trajectory as a keyframe CSV (the format scripted_trajectory.h reads), to `file`.
[[nodiscard]] Status save_trajectory_csv(const hardware::ScriptedTrajectory& trajectory,
                                         const std::filesystem::path& file);

}  // namespace lap::sim
