// The scenarios with a task: the introductory one on stand-in organs, the default (the textbook
// patient) and the patients of graded difficulty (scenarios/default.yaml and patient_*.yaml on
// the generated anatomy, docs/anatomy.md; issue 22): for each, the shipped scripts are what the
// planner (sim/authoring/expert_run.h) writes from the scenario, the expert's run ends in success
// and each clumsy run fails for its own reason, with the exact sequence of events
// (sim/runtime/task_engine.h). All in --fast mode: a function of the inputs only.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "haptics/closest_point.h"
#include "sim/authoring/expert_run.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

double metric(const SessionMetrics& m, const std::string& name) {
  for (const Metric& x : m.training) {
    if (x.name == name) return x.value;
  }
  ADD_FAILURE() << "no metric " << name;
  return 0.0;
}

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

struct Patient {
  std::string stem;  ///< scenarios/<stem>.yaml, scripts in scenarios/scripts/<stem>/
  /// The left hand steadies the duct (else it waits in view: no clear line from its port).
  bool steadies_duct = true;
};

// The test's name in ctest says the scenario (gtest would print the struct's bytes).
void PrintTo(const Patient& p, std::ostream* os) { *os << p.stem; }

const Scene& scene_of(const Patient& p) {
  static std::map<std::string, SceneLoadResult> loaded;
  auto it = loaded.find(p.stem);
  if (it == loaded.end()) {
    it =
        loaded
            .emplace(p.stem, load_scene_file(test::source_dir() / "scenarios" / (p.stem + ".yaml")))
            .first;
  }
  EXPECT_TRUE(it->second.ok()) << it->second.message();
  return it->second.value();
}

fs::path scripts_of(const Patient& p) { return test::source_dir() / "scenarios/scripts" / p.stem; }

// Whether the planner has the left hand steady the duct (ExpertRun::steady_site_m): where a line
// from the left tool's port reaches the duct beside the incision clear of the other organs.
bool steadies(const Patient& p) {
  RuntimeSettings rs;
  rs.fast = true;
  const auto model =
      SessionModel::build(scene_of(p), rs, {DeviceDescription{"left", {}}, {"right", {}}});
  EXPECT_TRUE(model.ok()) << model.message();
  const Result<ExpertRun> plan =
      plan_expert_run(scene_of(p), *model.value(), expert_run_settings(scene_of(p).scenario));
  EXPECT_TRUE(plan.ok()) << plan.message();
  return plan.ok() && plan.value().steady_site_m.has_value();
}

class PatientRun : public ::testing::TestWithParam<Patient> {};

TEST_P(PatientRun, TheShippedScriptsAreWhatThePlannerWritesFromTheScenario) {
  expect_planned_scripts(scene_of(GetParam()), ExpertMistake::kNone, scripts_of(GetParam()),
                         "expert");
  for (const ExpertMistake mistake : kClumsyRuns) {
    if (mistake == ExpertMistake::kEntersCommonBileDuct &&
        scene_of(GetParam()).scenario.task->common_bile_duct.empty()) {
      continue;  // the introductory scene has no common bile duct: no such run
    }
    expect_planned_scripts(scene_of(GetParam()), mistake, scripts_of(GetParam()),
                           "clumsy_" + std::string(to_string(mistake)));
  }
}

// The expert's run ends in success, and the left hand steadies the duct beside the incision while
// the catheter goes in (issue 22, "the procedure, as it is done"): it has taken the duct before
// the tip reaches the incision and holds it to the end, gently: its jaws' squeeze below a tenth
// of the task's threshold, the duct's load below the injury threshold (the run's events have no
// duct_injury). One test, as both are about the one expert session.
TEST_P(PatientRun, TheExpertInsertsTheCatheterAndHoldsIt) {
  const Scene& scene = scene_of(GetParam());
  Devices devices = scripted_devices(scripts_of(GetParam()), "expert");
  auto left = hardware::load_scripted_trajectory(scripts_of(GetParam()) / "expert_left.csv");
  ASSERT_TRUE(left.ok()) << left.message();
  auto watched =
      std::make_unique<FaultyDevice>(std::move(left).value(), FaultyDevice::Fault::kNone, -1);
  FaultyDevice* watch = watched.get();
  watch->commands.reserve(60001);
  devices[0] = std::move(watched);
  auto created = Session::create(scene, std::move(devices), fast(60.0));
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  double held_from_s = -1.0;
  int64_t held_ticks = 0;
  int64_t ticks = 0;
  watch->on_read = [&](int64_t tick) {
    if (tick == 0) return;
    ++ticks;
    if (session.graphics_model().duct_grasps[0].grasping()) {
      if (held_from_s < 0.0) held_from_s = 1e-3 * static_cast<double>(tick);
      ++held_ticks;
    } else {
      held_from_s = -1.0;  // held without letting go from then on
      held_ticks = 0;
    }
  };
  const SessionMetrics m = session.run();
  ASSERT_TRUE(expect_expert_success(m, *scene.scenario.task));
  // Gently: a fraction of a newton at the hands (nothing pressed on the way).
  EXPECT_LT(m.max_force_sent_n, 1.0);
  ASSERT_GE(m.task.phase_s[1], 0.0);
  ASSERT_EQ(steadies(GetParam()), GetParam().steadies_duct);
  if (!GetParam().steadies_duct) {
    // From the left tool's port every line to the duct beside the incision passes through the
    // gallbladder: the planner has it wait in view instead, and it never holds the duct.
    EXPECT_LT(held_from_s, 0.0);
    std::printf("[ steady ] %s: the left hand waits in view\n", GetParam().stem.c_str());
    return;
  }
  std::printf(
      "[ steady ] %s: the left hand holds the duct from %.3f s (the tip at the incision at "
      "%.3f s) to the end (%lld of %lld ticks); its squeeze at most %.3f N, the duct's load "
      "at most %.3f N\n",
      GetParam().stem.c_str(), held_from_s, m.task.phase_s[1], static_cast<long long>(held_ticks),
      static_cast<long long>(ticks), metric(m, "max_squeeze_duct_n"),
      metric(m, "max_force_duct_n"));
  EXPECT_GE(held_from_s, 0.0);
  EXPECT_LT(held_from_s, m.task.phase_s[1]);
  EXPECT_LT(metric(m, "max_squeeze_duct_n"), 0.1 * scene.scenario.task->duct_squeeze_n);
  EXPECT_LT(metric(m, "max_force_duct_n"), scene.scenario.task->duct_injury_force_n);
}

TEST_P(PatientRun, ACatheterLetGoOnTheWayIsDropped) {
  const Scene& scene = scene_of(GetParam());
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_drop");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, catheter_released, catheter_dropped, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCatheterDropped);
  ASSERT_EQ(m.task.events.size(), 4U);
  EXPECT_NEAR(m.task.events[2].t_s - m.task.events[1].t_s, scene.scenario.task->drop_grace_s,
              0.006);
}

TEST_P(PatientRun, PushingOnPastTheTargetPerforatesTheWall) {
  const SessionMetrics m =
      run_scripts(scene_of(GetParam()), scripts_of(GetParam()), "clumsy_overshoot");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task),
            "catheter_grasped, tip_at_incision, tip_in_lumen, target_depth_reached, "
            "wall_perforation, target_depth_lost, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kWallPerforation);
}

// The common bile duct taken for the cystic duct: the catheter pushed in through its wall, the
// task's error for a catheter meant for the cystic duct alone. The introductory scene has no
// common bile duct (its stand-in organs are the liver, the gallbladder and the cystic duct), so no
// such run (tests/sim/expert_run_test.cpp checks the error there with the duct standing in).
TEST_P(PatientRun, TheCommonBileDuctTakenForTheCysticDuctIsAnError) {
  const Scene& scene = scene_of(GetParam());
  if (scene.scenario.task->common_bile_duct.empty()) GTEST_SKIP() << "no common bile duct";
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_cbd");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, tip_in_common_bile_duct, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kCommonBileDuct);
  ASSERT_EQ(m.task.events.size(), 3U);
  EXPECT_EQ(scene.scenario.organs[static_cast<size_t>(m.task.events[1].organ)].name,
            scene.scenario.task->common_bile_duct);
}

// The hesitant hand brings the tip in front of the incision and never puts it in: the time
// limit ends the task. The shipped script outlasts the scenario's own limit (600 s); run here
// against a limit of 25 s, which it outlasts the same way, to keep the test short (the full
// run's events are in each scenario's STATUS comment).
TEST_P(PatientRun, HesitatingAtTheIncisionRunsOutOfTime) {
  Scene scene = scene_of(GetParam());
  const auto right =
      hardware::load_scripted_trajectory(scripts_of(GetParam()) / "clumsy_time_limit_right.csv");
  ASSERT_TRUE(right.ok()) << right.message();
  EXPECT_GT(right.value().duration_s(), scene.scenario.task->time_limit_s);
  scene.scenario.task->time_limit_s = 25.0;
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_time_limit");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "catheter_grasped, time_limit, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kTimeLimit);
  EXPECT_NEAR(m.task.end_s, 25.0, 0.006);
}

TEST_P(PatientRun, PullingTheGraspedDuctInjuresIt) {
  const Scene& scene = scene_of(GetParam());
  const SessionMetrics m = run_scripts(scene, scripts_of(GetParam()), "clumsy_tear");
  EXPECT_EQ(m.task.result, TaskResult::kFailure);
  EXPECT_EQ(event_kinds(m.task), "duct_injury, failure");
  ASSERT_EQ(m.task.reason_count, 1U);
  EXPECT_EQ(m.task.reasons[0], TaskReason::kDuctInjury);
  const TaskEvent& e = m.task.events[0];
  EXPECT_FALSE(e.squeeze);  // by the pull, not the jaws' squeeze
  EXPECT_GT(e.value, scene.scenario.task->duct_injury_force_n);
  EXPECT_NEAR(e.duration_s, scene.scenario.task->duct_injury_time_s, 0.006);
}

// Under the sanitizers, the introductory scene and the hardest patient only: the patients differ
// in their data, not in the code their runs go through, and there each run takes up to a minute
// (the Release build runs all five).
std::vector<Patient> patients() {
  if (test::kSanitizerDivisor > 1) {
    return {Patient{"introductory", false}, Patient{"patient_hard"}};
  }
  return {Patient{"introductory", false}, Patient{"default"}, Patient{"patient_easy"},
          Patient{"patient_moderate"}, Patient{"patient_hard"}};
}

// The right hand's clearances the planner reports (ExpertRun::right_shaft, held_catheter) are
// the least distances, found here by brute force over every face of every organ but the duct,
// from its keyframes as written: the shaft from the port to the hinge, and from the grasp on the
// held catheter from where the jaws hold it to its tip (rigid in the jaws' frame,
// models/catheter_grasp.h: where its tip lay when they closed on it), each every 1 mm.
TEST_P(PatientRun, ThePlannedRightHandsClearancesAreTheLeastDistancesOverItsKeyframes) {
  const Scene& scene = scene_of(GetParam());
  RuntimeSettings rs;
  rs.fast = true;
  const auto model = SessionModel::build(scene, rs, {DeviceDescription{"left", {}}, {"right", {}}});
  ASSERT_TRUE(model.ok()) << model.message();
  const ExpertRunSettings settings = expert_run_settings(scene.scenario);
  const Result<ExpertRun> plan = plan_expert_run(scene, *model.value(), settings);
  ASSERT_TRUE(plan.ok()) << plan.message();
  const std::vector<const haptics::MeshDatabase*> organs = model.value()->rest_databases();
  const int32_t duct = model.value()->tissue().duct_organ();
  // Each face's bounding sphere (its centroid, the farthest corner from it): a face farther than
  // the nearest one found so far by its sphere is skipped, the rest measured exactly.
  std::vector<std::vector<std::pair<Eigen::Vector3d, double>>> spheres(organs.size());
  for (size_t o = 0; o < organs.size(); ++o) {
    const haptics::MeshDatabase& db = *organs[o];
    for (int32_t f = 0; f < db.face_count(); ++f) {
      const auto& fv = db.face_vertices(f);
      const Eigen::Vector3d c = (db.position(fv[0]) + db.position(fv[1]) + db.position(fv[2])) / 3;
      double r = 0.0;
      for (const int32_t v : fv) r = std::max(r, (db.position(v) - c).norm());
      spheres[o].emplace_back(c, r);
    }
  }
  // Each organ's bounding box: a point outside it is outside the organ.
  std::vector<Eigen::AlignedBox3d> boxes(organs.size());
  for (size_t o = 0; o < organs.size(); ++o) {
    for (int32_t v = 0; v < organs[o]->vertex_count(); ++v) boxes[o].extend(organs[o]->position(v));
  }
  // Inside organ o: a ray from x crosses its (closed) surface an odd number of times (the
  // planner's ray direction: askew to the axes; Moller-Trumbore against every face).
  const Eigen::Vector3d ray = Eigen::Vector3d(0.31, 0.83, 0.47).normalized();
  auto inside = [&](size_t o, const Eigen::Vector3d& x) {
    if (!boxes[o].contains(x)) return false;
    const haptics::MeshDatabase& db = *organs[o];
    int crossings = 0;
    for (int32_t f = 0; f < db.face_count(); ++f) {
      const auto& fv = db.face_vertices(f);
      const Eigen::Vector3d e1 = db.position(fv[1]) - db.position(fv[0]);
      const Eigen::Vector3d e2 = db.position(fv[2]) - db.position(fv[0]);
      const Eigen::Vector3d p = ray.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-300) continue;
      const Eigen::Vector3d s0 = x - db.position(fv[0]);
      const double u = s0.dot(p) / det;
      const Eigen::Vector3d qv = s0.cross(e1);
      const double w = ray.dot(qv) / det;
      const double t = e2.dot(qv) / det;
      if (u >= 0.0 && w >= 0.0 && u + w <= 1.0 && t > 0.0) ++crossings;
    }
    return crossings % 2 == 1;
  };
  // The least signed distance (negative inside) from segment a-b (every 1 mm) to every organ
  // but the duct: the nearest point over every face, the sign by the ray's crossings.
  auto least_to_organs = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    PlannedClearance c;
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.001 - 1e-6)));
    for (size_t o = 0; o < organs.size(); ++o) {
      if (static_cast<int32_t>(o) == duct) continue;
      const haptics::MeshDatabase& db = *organs[o];
      for (int i = 0; i <= n; ++i) {
        const Eigen::Vector3d x = a + (b - a) * (static_cast<double>(i) / n);
        double nearest = std::numeric_limits<double>::infinity();
        for (int32_t f = 0; f < db.face_count(); ++f) {
          const auto& [centre, radius] = spheres[o][static_cast<size_t>(f)];
          if ((x - centre).norm() - radius > nearest) continue;
          const auto& fv = db.face_vertices(f);
          haptics::TriangleFeature feature{};
          nearest = std::min(
              nearest, (haptics::closest_on_triangle(x, db.position(fv[0]), db.position(fv[1]),
                                                     db.position(fv[2]), &feature) -
                        x)
                           .norm());
        }
        const double d = inside(o, x) ? -nearest : nearest;
        if (d < c.least_m) {
          c.least_m = d;
          c.organ = static_cast<int32_t>(o);
        }
      }
    }
    return c;
  };
  const TrocarToolSettings& trocar = model.value()->tool(1).trocar;
  const TissueWorldSettings& ws = model.value()->tissue().settings();
  const Eigen::Vector3d cath_dir = ws.catheter_direction_W.normalized();
  const Eigen::Vector3d cath_tip = ws.catheter_start_W + ws.catheter.length_m * cath_dir;
  const double held_depth = settings.grasp_depth * model.value()->tool(1).gripper.jaw_length_m;
  // Per keyframe time, each clearance; and the least over the run.
  std::map<double, std::array<PlannedClearance, 2>> at;
  std::array<PlannedClearance, 2> least;
  std::optional<Eigen::Vector3d> tip_J;
  for (const hardware::Keyframe& k : plan.value().right.keyframes) {
    // The handle is on the port's line, the shaft's length from the hinge.
    const Eigen::Vector3d y = (k.position_W - trocar.port_W).normalized();  // to the handle
    const Eigen::Vector3d hinge = k.position_W - trocar.shaft_length_m * y;
    std::array<PlannedClearance, 2>& here = at[k.time_s];
    here[0] = least_to_organs(trocar.port_W, hinge);
    if (k.gripper_angle_rad <= settings.grip_closed_rad) {
      Eigen::Vector3d x = k.orientation_W * Eigen::Vector3d::UnitX();
      x = (x - x.dot(y) * y).normalized();
      Eigen::Matrix3d frame;
      frame << x, y, x.cross(y);
      if (!tip_J) tip_J = frame.transpose() * (cath_tip - hinge);  // closing on it as it lies
      here[1] = least_to_organs(hinge + frame * Eigen::Vector3d(0.0, -held_depth, 0.0),
                                hinge + frame * *tip_J);
    }
    for (size_t i = 0; i < 2; ++i) {
      if (here[i].least_m < least[i].least_m) least[i] = here[i];
    }
  }
  // The poses rebuilt here from the keyframes (a handle position and a quaternion) agree with the
  // planner's to about 1e-15 m.
  constexpr double kToleranceM = 1e-9;
  const std::vector<std::string>& names = model.value()->organ_names();
  const std::array<PlannedClearance, 2> got = {plan.value().right_shaft,
                                               plan.value().held_catheter};
  for (size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE(i == 0 ? "shaft" : "held catheter");
    ASSERT_GE(least[i].organ, 0);
    EXPECT_NEAR(got[i].least_m, least[i].least_m, kToleranceM);
    EXPECT_EQ(got[i].organ, least[i].organ);
    ASSERT_EQ(at.count(got[i].time_s), 1U) << got[i].time_s;  // a keyframe's time
    EXPECT_NEAR(at[got[i].time_s][i].least_m, got[i].least_m, kToleranceM);
    std::printf("[ clearance ] %s: the right %s within %.2f mm of the %s at %.1f s (%.2f mm in)\n",
                GetParam().stem.c_str(), i == 0 ? "shaft" : "held catheter", got[i].least_m * 1e3,
                names[static_cast<size_t>(got[i].organ)].c_str(), got[i].time_s,
                got[i].pressed_in_m() * 1e3);
  }
  EXPECT_EQ(plan.value().right_shaft.radius_m, 0.0025);  // the scenarios' default shaft
  EXPECT_EQ(plan.value().held_catheter.radius_m, 0.5 * scene.scenario.catheter->diameter_m);
}

// The hardest patient's expert comes in at the slant its scenario names (task.
// expert_entry_slant_deg: 42 degrees to the duct's axis), the others at the planner's 39; the
// reason, from the geometry alone: through the right hand's port the fulcrum points the catheter
// nearer the wanted direction at 42 than at 39 (at 39 the keyboard's tip slid off the wall beside
// the incision: docs/benchmarks.md, "Why the keys miss the hardest patient's incision"). The bounds
// hold the geometry measured when the slant was chosen (2.76 and 5.31 degrees) with some room: a
// check that the reason still holds, not of where the tip then enters (the runs below and
// KeyboardRun's check that).
TEST(PatientApproach, TheHardestPatientsExpertComesInAtTheSlantItsFulcrumMeetsBetter) {
  const Patient hard{"patient_hard"};
  EXPECT_EQ(expert_run_settings(scene_of(Patient{"default"}).scenario).entry_slant_deg, 39.0);
  const ExpertRunSettings named = expert_run_settings(scene_of(hard).scenario);
  EXPECT_EQ(named.entry_slant_deg, 42.0);
  RuntimeSettings rs;
  rs.fast = true;
  const auto model =
      SessionModel::build(scene_of(hard), rs, {DeviceDescription{"left", {}}, {"right", {}}});
  ASSERT_TRUE(model.ok()) << model.message();
  ExpertRunSettings planners = named;
  planners.entry_slant_deg = 39.0;
  const Result<ExpertRun> at42 = plan_expert_run(scene_of(hard), *model.value(), named);
  const Result<ExpertRun> at39 = plan_expert_run(scene_of(hard), *model.value(), planners);
  ASSERT_TRUE(at42.ok() && at39.ok());
  std::printf(
      "[ slant ] patient_hard: the catheter within %.2f degrees of the planned entry at "
      "42, %.2f at 39\n",
      at42.value().worst_direction_error_deg, at39.value().worst_direction_error_deg);
  EXPECT_LT(at42.value().worst_direction_error_deg, 3.0);
  EXPECT_GT(at39.value().worst_direction_error_deg, 5.0);
}

INSTANTIATE_TEST_SUITE_P(Patients, PatientRun, ::testing::ValuesIn(patients()),
                         [](const ::testing::TestParamInfo<Patient>& info) {
                           return info.param.stem;
                         });

}  // namespace
}  // namespace lap::sim
