#include "app/hud_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/setup/tool_model.h"

namespace lap::app {
namespace {

std::string fixed(double value, int decimals) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

std::string reason_text(sim::TaskReason r) {
  switch (r) {
    case sim::TaskReason::kCatheterDropped:
      return "catheter dropped";
    case sim::TaskReason::kDuctInjury:
      return "duct injured";
    case sim::TaskReason::kOrganInjury:
      return "organ injured";
    case sim::TaskReason::kWallPerforation:
      return "duct wall perforated";
    case sim::TaskReason::kTimeLimit:
      return "time is up";
    case sim::TaskReason::kOutOfView:
      return "instrument out of view";
    case sim::TaskReason::kForbiddenContact:
      return "forbidden organ touched";
    case sim::TaskReason::kCommonBileDuct:
      return "catheter in the common bile duct";
  }
  return "error";
}

std::string hand(int32_t tool) {
  if (tool == 0) return "left";
  if (tool == 1) return "right";
  return "";
}

}  // namespace

std::string clock_text(double seconds) {
  const auto s = static_cast<int64_t>(std::floor(std::max(0.0, seconds)));
  char text[32];
  std::snprintf(text, sizeof(text), "%02lld:%02lld", static_cast<long long>(s / 60),
                static_cast<long long>(s % 60));
  return text;
}

HudModel::HudModel(const sim::Scenario& scenario, std::vector<std::string> organ_names)
    : organ_names_(std::move(organ_names)) {
  if (scenario.task) {
    spec_ = *scenario.task;
    has_task_ = true;
  }
  // A hand pushing nothing shows the threshold it will meet first: the duct's where the scene
  // has the task's duct, any organ's otherwise (the thesis' demonstrations have no duct).
  const bool duct = has_task_ && std::find(organ_names_.begin(), organ_names_.end(),
                                           spec_.target) != organ_names_.end();
  idle_threshold_n_ = duct ? spec_.duct_injury_force_n : spec_.organ_injury_force_n;
  for (size_t i = 0; i < 2; ++i) {
    const sim::ToolSpec* t =
        scenario.tool(i == 0 ? sim::ToolSpec::Side::kLeft : sim::ToolSpec::Side::kRight);
    tool_kinds_[i] = t != nullptr ? t->kind : "grasper";
  }
}

std::string HudModel::event_text(const sim::TaskEvent& e) const {
  const std::string organ = e.organ >= 0 && static_cast<size_t>(e.organ) < organ_names_.size()
                                ? organ_names_[static_cast<size_t>(e.organ)]
                                : std::string("organ");
  switch (e.kind) {
    case sim::TaskEventKind::kCatheterGrasped:
      return "Catheter grasped (" + hand(e.tool) + ")";
    case sim::TaskEventKind::kCatheterReleased:
      return "Catheter released (" + hand(e.tool) + ")";
    case sim::TaskEventKind::kTipAtIncision:
      return "Tip at the ductotomy";
    case sim::TaskEventKind::kTipInLumen:
      return "Tip in the duct";
    case sim::TaskEventKind::kTipEnteredOpenEnd:
      return "Tip entered the duct's open end";
    case sim::TaskEventKind::kTipLeftLumen:
      return "Tip left the duct";
    case sim::TaskEventKind::kTargetDepthReached:
      return "Target depth reached: hold it";
    case sim::TaskEventKind::kTargetDepthLost:
      return "Target depth lost";
    case sim::TaskEventKind::kSuccess:
      return "Catheter in place";
    case sim::TaskEventKind::kCatheterDropped:
      return "Catheter dropped";
    case sim::TaskEventKind::kDuctInjury:
      return e.squeeze ? "Duct crushed by the jaws (" + fixed(e.value, 1) + " N)"
                       : "Duct injured (" + fixed(e.value, 1) + " N)";
    case sim::TaskEventKind::kOrganInjury:
      return organ + " injured (" + fixed(e.value, 1) + " N)";
    case sim::TaskEventKind::kWallPerforation:
      return "Duct wall perforated";
    case sim::TaskEventKind::kTimeLimit:
      return "Time is up";
    case sim::TaskEventKind::kOutOfView:
      return "The " + hand(e.tool) + " instrument is out of view";
    case sim::TaskEventKind::kForbiddenContact:
      return "Touched the " + organ;
    case sim::TaskEventKind::kTipInCommonBileDuct:
      return "Catheter in the common bile duct";
    case sim::TaskEventKind::kFailure:
      return "";  // the result says it
  }
  return "";
}

void HudModel::take_events(const sim::TaskProgress& task, double now_s) {
  const int64_t fresh = task.event_count - events_seen_;
  if (fresh < 0) events_seen_ = 0;  // a new session
  if (fresh > 0) {
    const int64_t n = std::min<int64_t>(fresh, task.recent_count);
    for (int64_t k = task.recent_count - n; k < task.recent_count; ++k) {
      const sim::TaskEvent& e = task.recent[static_cast<size_t>(k)];
      const std::string text = event_text(e);
      if (text.empty()) continue;
      const bool alarm = e.kind >= sim::TaskEventKind::kCatheterDropped;
      shown_.push_back({text, alarm, now_s});
    }
  }
  events_seen_ = task.event_count;
  while (!shown_.empty() && now_s - shown_.front().since_s > kNoticeHoldS + kNoticeFadeS) {
    shown_.pop_front();
  }
  while (shown_.size() > kMaxNotices) shown_.pop_front();
}

const HudState& HudModel::update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model,
                                 const ScopeFigures& scope, double now_s) {
  const sim::TaskProgress& task = model.task;
  HudState& s = state_;
  take_events(task, now_s);

  // Instruction and step.
  const double depth_mm = spec_.insertion_depth_m * 1e3;
  s.progress.clear();
  s.result.clear();
  s.failed = false;
  switch (task.stage) {
    case sim::TaskStage::kNone:
      s.instruction = task.kind == sim::TaskKind::kFreeExploration
                          ? "Explore the field: keep the instruments in view, injure nothing"
                          : "Free practice: no task in this scenario";
      s.step = task.kind == sim::TaskKind::kFreeExploration ? "Free exploration" : "";
      break;
    case sim::TaskStage::kGraspCatheter:
      s.instruction = "Grasp the catheter a few centimetres behind its tip";
      s.step = "Step 1 of 5";
      break;
    case sim::TaskStage::kBringToIncision:
      s.instruction = "Bring the catheter's tip to the ductotomy in the cystic duct";
      s.step = "Step 2 of 5";
      break;
    case sim::TaskStage::kEnterIncision:
      s.instruction = "Pass the tip through the ductotomy into the duct";
      s.step = "Step 3 of 5";
      break;
    case sim::TaskStage::kAdvance:
      s.instruction = "Advance the catheter " + fixed(depth_mm, 0) + " mm into the duct";
      s.step = "Step 4 of 5";
      break;
    case sim::TaskStage::kHold:
      s.instruction = "Hold it there, without pushing the duct";
      s.step = "Step 5 of 5";
      s.progress = "Held " + fixed(task.held_for_s, 1) + " of " + fixed(spec_.hold_s, 1) + " s";
      break;
    case sim::TaskStage::kDone:
      s.step = "Done";
      if (task.result == sim::TaskResult::kSuccess) {
        s.instruction = "The catheter is in the cystic duct: task complete";
        s.result = "SUCCESS  " + clock_text(task.t_s);
      } else {
        s.failed = true;
        std::string why;
        for (int32_t k = 0; k < task.reason_count; ++k) {
          why += (k > 0 ? ", " : "") + reason_text(task.reasons[static_cast<size_t>(k)]);
        }
        s.instruction = "The task has ended";
        s.result = "FAILED: " + (why.empty() ? std::string("task failed") : why);
      }
      break;
  }
  if (task.stage == sim::TaskStage::kAdvance || task.stage == sim::TaskStage::kEnterIncision) {
    s.progress = "Depth " + fixed(task.depth_m * 1e3, 1) + " of " + fixed(depth_mm, 1) + " mm";
  }
  s.timer = clock_text(task.t_s);
  if (task.kind == sim::TaskKind::kCatheterInsertion)
    s.timer += " / " + clock_text(spec_.time_limit_s);

  // Per hand: the push nearer its own threshold, and the squeeze.
  for (size_t i = 0; i < 2; ++i) {
    HandGauge& g = s.hands[i];
    const sim::ToolForces& f = task.tools[i];
    g.label = std::string(i == 0 ? "Left " : "Right ") + tool_kinds_[i];
    g.jaws = sim::tool_kind(tool_kinds_[i]) == sim::ToolKind::kGripper;
    const double duct_share = f.on_duct_n / spec_.duct_injury_force_n;
    const double organ_share = f.on_organ_n / spec_.organ_injury_force_n;
    if (duct_share >= organ_share && f.on_duct_n > 0.0) {
      g.force_n = f.on_duct_n;
      g.threshold_n = spec_.duct_injury_force_n;
      g.pushing = "duct";
    } else if (f.on_organ_n > 0.0) {
      g.force_n = f.on_organ_n;
      g.threshold_n = spec_.organ_injury_force_n;
      g.pushing = f.organ >= 0 && static_cast<size_t>(f.organ) < organ_names_.size()
                      ? organ_names_[static_cast<size_t>(f.organ)]
                      : "organ";
    } else {
      g.force_n = 0.0;
      g.threshold_n = idle_threshold_n_;
      g.pushing.clear();
    }
    g.fraction = g.threshold_n > 0.0 ? g.force_n / g.threshold_n : 0.0;
    g.squeeze_n = std::max(model.squeeze[i], f.duct_squeeze_n);
    g.squeeze_threshold_n = spec_.duct_squeeze_n;
    const double squeeze_share =
        f.duct_squeeze_n > 0.0 ? f.duct_squeeze_n / spec_.duct_squeeze_n : 0.0;
    const double worst = std::max(g.fraction, squeeze_share);
    g.warning = worst >= 0.8;
    g.over = worst > 1.0;
  }

  // Notices, fading.
  s.notices.clear();
  for (const Shown& n : shown_) {
    const double age = now_s - n.since_s;
    const double opacity =
        age <= kNoticeHoldS ? 1.0 : std::max(0.0, 1.0 - (age - kNoticeHoldS) / kNoticeFadeS);
    if (opacity > 0.0) s.notices.push_back({n.text, opacity, n.alarm});
  }

  // The loops: quiet unless they paused.
  s.loops_alarm = haptic.paused;
  if (haptic.paused) {
    s.loops = "PAUSED: forces off - press Space to resume";
  } else if (haptic.late_ticks > 0) {
    s.loops = std::to_string(haptic.late_ticks) + " late haptic tick" +
              (haptic.late_ticks == 1 ? "" : "s");
  } else {
    s.loops.clear();
  }
  s.scope = fixed(scope.optics_deg, 0) + "\xC2\xB0 scope  zoom " + fixed(scope.zoom, 1) + "x" +
            (scope.assistant ? "  camera assistant" : "");
  return s;
}

}  // namespace lap::app
