// The heads-up display's contents (app/hud_state.h), read without pixels: the instruction and
// step for each stage, the timer against the limit, the depth and the hold; per hand the push
// nearer its own injury threshold and the squeeze; notices of events that fade after their few
// seconds; the late ticks quietly, a pause loudly.

#include "app/hud_state.h"

#include <gtest/gtest.h>

#include "sim/setup/scenario_loader.h"
#include "tests/test_support.h"

namespace lap::app {
namespace {

sim::Scenario introductory_scenario() {
  const sim::ScenarioLoadResult r =
      sim::load_scenario(test::source_dir() / "scenarios/introductory.yaml");
  EXPECT_TRUE(r.ok()) << r.message();
  return r.value();
}

const std::vector<std::string> kOrgans = {"liver", "gallbladder", "cystic_duct"};

TEST(HudState, TheInstructionFollowsTheStage) {
  HudModel hud(introductory_scenario(), kOrgans);
  sim::HapticSnapshot h;
  sim::ModelSnapshot m;
  m.task.kind = sim::TaskKind::kCatheterInsertion;
  m.task.stage = sim::TaskStage::kGraspCatheter;
  m.task.t_s = 83.4;
  const HudState& s = hud.update(h, m, {}, 0.0);
  EXPECT_EQ(s.step, "Step 1 of 5");
  EXPECT_NE(s.instruction.find("Grasp the catheter"), std::string::npos);
  EXPECT_EQ(s.timer, "01:23 / 10:00");  // the introductory scene's 600 s limit
  EXPECT_TRUE(s.result.empty());

  m.task.stage = sim::TaskStage::kAdvance;
  m.task.depth_m = 0.0062;
  hud.update(h, m, {}, 0.1);
  EXPECT_EQ(hud.state().step, "Step 4 of 5");
  EXPECT_EQ(hud.state().instruction, "Advance the catheter 10 mm into the duct");
  EXPECT_EQ(hud.state().progress, "Depth 6.2 of 10.0 mm");

  m.task.stage = sim::TaskStage::kHold;
  m.task.held_for_s = 1.25;
  hud.update(h, m, {}, 0.2);
  EXPECT_EQ(hud.state().progress, "Held 1.2 of 3.0 s");

  m.task.stage = sim::TaskStage::kDone;
  m.task.result = sim::TaskResult::kFailure;
  m.task.reasons[0] = sim::TaskReason::kDuctInjury;
  m.task.reasons[1] = sim::TaskReason::kCatheterDropped;
  m.task.reason_count = 2;
  hud.update(h, m, {}, 0.3);
  EXPECT_EQ(hud.state().result, "FAILED: duct injured, catheter dropped");
  EXPECT_TRUE(hud.state().failed);
}

// Left: 1.5 N on the duct (0.75 of its 2 N) against 2 N on the liver (0.4 of 5 N): the duct's
// gauge, amber. Right: 6 N on the liver: over its 5 N, red, whatever it does not push.
TEST(HudState, EachHandsGaugeIsThePushNearestItsThreshold) {
  HudModel hud(introductory_scenario(), kOrgans);
  sim::HapticSnapshot h;
  sim::ModelSnapshot m;
  m.task.tools[0] = {1.5, 2.0, 0, 0.0};
  m.task.tools[1] = {0.0, 6.0, 0, 0.0};
  m.squeeze = {0.8, 0.0};
  const HudState& s = hud.update(h, m, {}, 0.0);
  EXPECT_EQ(s.hands[0].pushing, "duct");
  EXPECT_EQ(s.hands[0].force_n, 1.5);
  EXPECT_EQ(s.hands[0].threshold_n, 2.0);
  EXPECT_DOUBLE_EQ(s.hands[0].fraction, 0.75);
  EXPECT_FALSE(s.hands[0].warning);
  EXPECT_EQ(s.hands[0].squeeze_n, 0.8);
  EXPECT_EQ(s.hands[0].squeeze_threshold_n, 5.0);
  EXPECT_EQ(s.hands[0].label, "Left grasper");
  EXPECT_EQ(s.hands[1].pushing, "liver");
  EXPECT_DOUBLE_EQ(s.hands[1].fraction, 1.2);
  EXPECT_TRUE(s.hands[1].over);
  // The jaws crushing the duct at 4.5 N (0.9 of 5 N): a warning though nothing is pushed.
  m.task.tools[0] = {0.0, 0.0, -1, 4.5};
  hud.update(h, m, {}, 0.1);
  EXPECT_TRUE(hud.state().hands[0].warning);
  EXPECT_EQ(hud.state().hands[0].squeeze_n, 4.5);
  EXPECT_TRUE(hud.state().hands[0].pushing.empty());
  EXPECT_TRUE(hud.state().hands[0].jaws);
}

// A probe (point or ray) has no jaws: its gauge says so, and the overlay draws no squeeze.
TEST(HudState, AProbesGaugeHasNoJaws) {
  sim::Scenario sc = introductory_scenario();
  for (sim::ToolSpec& t : sc.tools)
    t.kind = t.side == sim::ToolSpec::Side::kLeft ? "probe" : "ray-probe";
  HudModel hud(sc, kOrgans);
  const HudState& s = hud.update(sim::HapticSnapshot{}, sim::ModelSnapshot{}, {}, 0.0);
  EXPECT_EQ(s.hands[0].label, "Left probe");
  EXPECT_FALSE(s.hands[0].jaws);
  EXPECT_EQ(s.hands[1].label, "Right ray-probe");
  EXPECT_FALSE(s.hands[1].jaws);
}

// A hand pushing nothing shows the threshold it will meet first: the duct's in the procedure,
// any organ's in a scene without the task's duct (a demonstration of the thesis).
TEST(HudState, AnIdleGaugeShowsTheDuctsThresholdOnlyWhereThereIsADuct) {
  const sim::Scenario sc = introductory_scenario();
  ASSERT_TRUE(sc.task.has_value());
  ASSERT_NE(sc.task->duct_injury_force_n, sc.task->organ_injury_force_n);
  HudModel with_duct(sc, kOrgans);
  EXPECT_EQ(with_duct.update({}, {}, {}, 0.0).hands[0].threshold_n, sc.task->duct_injury_force_n);
  sim::Scenario free = sc;
  free.task.reset();
  HudModel demo(free, {"dumbbell_silver", "dumbbell_gold"});
  const HudState& s = demo.update({}, {}, {}, 0.0);
  EXPECT_EQ(s.hands[0].threshold_n, sim::TaskSpec{}.organ_injury_force_n);
  EXPECT_EQ(s.hands[1].threshold_n, sim::TaskSpec{}.organ_injury_force_n);
  EXPECT_TRUE(s.hands[0].pushing.empty());
}

// Events become notices when they appear, hold for 3 s, fade over 1.5 s and go; errors are
// alarms; the display keeps three at most.
TEST(HudState, EventNoticesFadeAfterAFewSeconds) {
  HudModel hud(introductory_scenario(), kOrgans);
  sim::HapticSnapshot h;
  sim::ModelSnapshot m;
  auto add = [&](sim::TaskEventKind kind, int32_t tool = -1) {
    m.task.recent[static_cast<size_t>(m.task.recent_count++)] = {0.0, kind, tool};
    ++m.task.event_count;
  };
  add(sim::TaskEventKind::kCatheterGrasped, 1);
  hud.update(h, m, {}, 10.0);
  ASSERT_EQ(hud.state().notices.size(), 1U);
  EXPECT_EQ(hud.state().notices[0].text, "Catheter grasped (right)");
  EXPECT_FALSE(hud.state().notices[0].alarm);
  add(sim::TaskEventKind::kCatheterDropped);
  hud.update(h, m, {}, 12.0);
  ASSERT_EQ(hud.state().notices.size(), 2U);
  EXPECT_EQ(hud.state().notices[1].text, "Catheter dropped");
  EXPECT_TRUE(hud.state().notices[1].alarm);
  // 13.75 s: the first is 3.75 s old, half faded; the second whole.
  hud.update(h, m, {}, 13.75);
  EXPECT_NEAR(hud.state().notices[0].opacity, 0.5, 1e-12);
  EXPECT_EQ(hud.state().notices[1].opacity, 1.0);
  // 14.6 s: the first is gone.
  hud.update(h, m, {}, 14.6);
  ASSERT_EQ(hud.state().notices.size(), 1U);
  EXPECT_EQ(hud.state().notices[0].text, "Catheter dropped");
  // Four at once: the newest three are shown; nothing is repeated on the next frame.
  add(sim::TaskEventKind::kTipAtIncision);
  add(sim::TaskEventKind::kTipInLumen);
  add(sim::TaskEventKind::kTargetDepthReached);
  add(sim::TaskEventKind::kDuctInjury);
  hud.update(h, m, {}, 15.0);
  ASSERT_EQ(hud.state().notices.size(), 3U);
  EXPECT_EQ(hud.state().notices[2].text, "Duct injured (0.0 N)");
  hud.update(h, m, {}, 15.1);
  EXPECT_EQ(hud.state().notices.size(), 3U);
}

TEST(HudState, LateTicksQuietlyAPauseLoudly) {
  HudModel hud(introductory_scenario(), kOrgans);
  sim::HapticSnapshot h;
  sim::ModelSnapshot m;
  EXPECT_TRUE(hud.update(h, m, {}, 0.0).loops.empty());
  h.late_ticks = 3;
  EXPECT_EQ(hud.update(h, m, {}, 0.0).loops, "3 late haptic ticks");
  EXPECT_FALSE(hud.state().loops_alarm);
  h.paused = true;
  EXPECT_NE(hud.update(h, m, {}, 0.0).loops.find("PAUSED"), std::string::npos);
  EXPECT_TRUE(hud.state().loops_alarm);
  const HudState& s = hud.update(h, m, {30.0, 1.5, true}, 0.0);
  EXPECT_EQ(s.scope, "30\xC2\xB0 scope  zoom 1.5x  camera assistant");
}

}  // namespace
}  // namespace lap::app
