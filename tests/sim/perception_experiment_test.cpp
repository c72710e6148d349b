// The §5.5 shape-perception experiment (sim/runtime/perception_experiment.h): the seeded
// sequence, scripted answers giving the table worked out by hand below, the script's errors, and
// each mode's trial scene felt through its probe in a session.

#include "sim/runtime/perception_experiment.h"

#include <gtest/gtest.h>

#include <map>

#include "sim/authoring/perception_trials.h"
#include "tests/sim/demo_test_support.h"

namespace lap::sim {
namespace {

TEST(PerceptionExperiment, TheSequenceIsSeededAndBalanced) {
  PerceptionSettings s;
  s.seed = 7;
  s.repetitions = 3;
  const auto a = PerceptionExperiment::create(s);
  const auto b = PerceptionExperiment::create(s);
  s.seed = 8;
  const auto c = PerceptionExperiment::create(s);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  ASSERT_EQ(a.value().trials().size(), 24U);  // 4 shapes × 2 modes × 3
  std::map<std::pair<int, int>, int> count;
  bool differs = false;
  for (size_t i = 0; i < 24; ++i) {
    const PerceptionTrial& t = a.value().trials()[i];
    ++count[{static_cast<int>(t.shape), static_cast<int>(t.mode)}];
    EXPECT_EQ(t.index, static_cast<int32_t>(i));
    EXPECT_NEAR(t.orientation.norm(), 1.0, 1e-12);
    EXPECT_EQ(t.shape, b.value().trials()[i].shape);
    EXPECT_EQ(t.orientation.coeffs(), b.value().trials()[i].orientation.coeffs());
    differs =
        differs || t.shape != c.value().trials()[i].shape || t.mode != c.value().trials()[i].mode;
  }
  EXPECT_EQ(count.size(), 8U);
  for (const auto& [key, n] : count) EXPECT_EQ(n, 3);
  EXPECT_TRUE(differs) << "another seed, another order";
  EXPECT_FALSE(PerceptionExperiment::create({1, 0, {ProbeMode::kPoint}}).ok());
}

// Two presentations of each shape in each mode; the times and answers are chosen so that the
// table can be worked out by hand:
//   sphere   point 4, 6 (both right): mean 5, sd √2 = 1.4142   ray 5, 5: mean 5, sd 0; 0 % faster
//   cone     point 10, 12 (the 2nd named cylinder): 1 of 2, mean 11, sd 1.4142
//            ray 8, 9.6: mean 8.8, sd √(0.8² + 0.8²) = 1.1314; (11 − 8.8) / 11 = 20 % faster
//   cylinder point 7, 7: sd 0   ray 6 (named cube), 8: 1 of 2, mean 7, sd 1.4142; 0 % faster
//   cube     point 9, 11: mean 10, sd 1.4142   ray 9, 9: mean 9; (10 − 9) / 10 = 10 % faster
constexpr const char* kScript = R"(shape,mode,repetition,named,time_s
# a scripted participant
sphere,point,0,sphere,4.0
sphere,point,1,sphere,6.0
sphere,ray,0,sphere,5.0
sphere,ray,1,sphere,5.0
cone,point,0,cone,10.0
cone,point,1,cylinder,12.0
cone,ray,0,cone,8.0
cone,ray,1,cone,9.6
cylinder,point,0,cylinder,7.0
cylinder,point,1,cylinder,7.0
cylinder,ray,0,cube,6.0
cylinder,ray,1,cylinder,8.0
cube,point,0,cube,9.0
cube,point,1,cube,11.0
cube,ray,0,cube,9.0
cube,ray,1,cube,9.0
)";

TEST(PerceptionExperiment, ScriptedAnswersGiveTheHandComputedTable) {
  auto e = PerceptionExperiment::create({7, 2, {ProbeMode::kPoint, ProbeMode::kRay}});
  ASSERT_TRUE(e.ok());
  const auto script = parse_scripted_answers(kScript, "answers.csv");
  ASSERT_TRUE(script.ok()) << script.message();
  const Status ran = run_scripted_answers(&e.value(), script.value());
  ASSERT_TRUE(ran.ok()) << ran.message();
  EXPECT_TRUE(e.value().done());
  ASSERT_EQ(e.value().answers().size(), 16U);
  EXPECT_EQ(to_csv(tabulate(e.value().answers())),
            "shape,mode,trials,correct,percent_correct,mean_time_s,sd_time_s,ray_faster_percent\n"
            "sphere,point,2,2,100.00,5.0000,1.4142,\n"
            "sphere,ray,2,2,100.00,5.0000,0.0000,0.00\n"
            "cone,point,2,1,50.00,11.0000,1.4142,\n"
            "cone,ray,2,2,100.00,8.8000,1.1314,20.00\n"
            "cylinder,point,2,2,100.00,7.0000,0.0000,\n"
            "cylinder,ray,2,1,50.00,7.0000,1.4142,0.00\n"
            "cube,point,2,2,100.00,10.0000,1.4142,\n"
            "cube,ray,2,2,100.00,9.0000,0.0000,10.00\n");
}

TEST(PerceptionExperiment, AnswersAndScriptsAreChecked) {
  auto e = PerceptionExperiment::create({});
  ASSERT_TRUE(e.ok());
  EXPECT_FALSE(e.value().answer(PerceivedShape::kCube, 1.0).ok()) << "not started";
  ASSERT_TRUE(e.value().start_trial(2.0).ok());
  EXPECT_FALSE(e.value().answer(PerceivedShape::kCube, 1.0).ok()) << "before its start";
  const auto bad = parse_scripted_answers("sphere,point,0,pyramid,3\n", "a.csv");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.message(),
            "a.csv:1: named: expected sphere, cone, cylinder or cube, got 'pyramid'");
  const auto bad_time = parse_scripted_answers("# x\ncube,ray,0,cube,-1\n", "b.csv");
  ASSERT_FALSE(bad_time.ok());
  EXPECT_EQ(bad_time.message(), "b.csv:2: time_s: expected a time of 0 s or more, got '-1'");
  auto short_script = PerceptionExperiment::create({});
  const Status missing = run_scripted_answers(&short_script.value(), {});
  EXPECT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("no scripted answer"), std::string::npos);
}

// Each mode's trial scene in a session: the probe lowered onto the shape from above meets it
// with the probe of its mode (a point probe's contacts, a ray's), and feels it push back.
TEST(PerceptionExperiment, EachModesTrialIsFeltThroughItsProbe) {
  for (const ProbeMode mode : {ProbeMode::kPoint, ProbeMode::kRay}) {
    PerceptionTrial trial;
    trial.shape = PerceivedShape::kCube;
    trial.mode = mode;
    trial.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
    const Scene scene = perception_scene(trial);
    ToolKind kind = ToolKind::kGripper;
    double most = 0.0;
    auto run = demo_test::observed_session(
        scene,
        {{{{0.0, Eigen::Vector3d(-0.15, 0.07, 0.0)}, {1.5, Eigen::Vector3d(-0.15, 0.07, 0.0)}},
          {{0.0, Eigen::Vector3d(0.0, 0.06, 0.0)}, {1.5, Eigen::Vector3d(0.0, 0.0, 0.0)}}}},
        1.5, [&](int64_t, const HapticSnapshot& h, const ModelSnapshot&) {
          kind = h.tools[1].kind;
          most = std::max(most, demo_test::tip_force(h.tools[1]).y());
        });
    ASSERT_NE(run.session, nullptr);
    run.session->run();
    EXPECT_EQ(kind, mode == ProbeMode::kPoint ? ToolKind::kPointProbe : ToolKind::kRayProbe);
    EXPECT_GT(most, 1.0) << to_string(mode) << ": pressed well into the cube";
  }
}

}  // namespace
}  // namespace lap::sim
