#pragma once
/// \file
/// What the heads-up display shows, as texts and values (no drawing here: hud_overlay draws
/// it, and tests read it without pixels): the task's instruction for the stage the trainee is at
/// and the step number, a timer against the time limit, the depth or the hold, the result when
/// the task ends; per hand a force gauge against the injury threshold that applies to what it
/// pushes (the duct's or another organ's) and the jaws' squeeze against the duct's; short
/// notices of the task's events that fade after a few seconds; and a quiet note of late haptic
/// ticks (a pause of the loops loudly). Built each frame from the newest snapshots
/// (TaskProgress in the model snapshot, the loop's figures in the haptic snapshot).

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "sim/runtime/session.h"
#include "sim/setup/scenario.h"

namespace lap::app {

/// One hand's gauge.
struct HandGauge {
  std::string label;         ///< "Left" or "Right", and the instrument's kind
  double force_n = 0.0;      ///< the push the injury thresholds watch (the nearer to its own)
  double threshold_n = 0.0;  ///< that push's injury threshold
  double fraction = 0.0;     ///< force / threshold
  std::string pushing;       ///< on what ("duct", an organ's name, or empty)
  double squeeze_n = 0.0;    ///< the jaws' squeeze on what they hold
  double squeeze_threshold_n = 0.0;  ///< the duct's crush threshold
  bool warning = false;              ///< at 80 % of a threshold or more
  bool over = false;                 ///< over a threshold (an injury if it lasts)
  bool jaws = true;                  ///< false for a probe: no squeeze to show
};

/// A notice of an event, fading.
struct HudNotice {
  std::string text;
  double opacity = 1.0;  ///< 1 for kNoticeHoldS, then down to 0 over kNoticeFadeS
  bool alarm = false;    ///< an error (drawn in red)
};

struct HudState {
  std::string instruction;  ///< what to do now
  std::string step;         ///< "Step 2 of 5", or the task's kind without steps
  std::string timer;        ///< "01:23 / 10:00"
  std::string progress;     ///< "Depth 6.2 of 10.0 mm", "Held 1.2 of 3.0 s", or empty
  std::string result;       ///< empty while running; "SUCCESS …" or "FAILED: …" at the end
  bool failed = false;
  std::array<HandGauge, 2> hands;
  std::vector<HudNotice> notices;  ///< newest last, at most kMaxNotices
  std::string loops;               ///< quiet: late haptic ticks; loud: a pause
  bool loops_alarm = false;        ///< the loops paused (forces off)
  std::string scope;               ///< the scope's optic, zoom and assistant, quiet
};

/// The scope's settings shown on the display.
struct ScopeFigures {
  double optics_deg = 0.0;
  double zoom = 1.0;  ///< the home view angle's half tangent over the current one's
  bool assistant = false;
};

class HudModel {
 public:
  static constexpr double kNoticeHoldS = 3.0;
  static constexpr double kNoticeFadeS = 1.5;
  static constexpr size_t kMaxNotices = 3;

  /// For a scenario (its task's thresholds and limit, its tools' kinds) and its organs' names.
  HudModel(const sim::Scenario& scenario, std::vector<std::string> organ_names);

  /// The display for the newest snapshots at `now_s` (the graphics loop's clock, for fading).
  const HudState& update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model,
                         const ScopeFigures& scope, double now_s);
  [[nodiscard]] const HudState& state() const { return state_; }

 private:
  struct Shown {
    std::string text;
    bool alarm = false;
    double since_s = 0.0;
  };
  void take_events(const sim::TaskProgress& task, double now_s);
  [[nodiscard]] std::string event_text(const sim::TaskEvent& e) const;

  sim::TaskSpec spec_;  ///< the thresholds (the defaults when the scenario has no task)
  bool has_task_ = false;
  double idle_threshold_n_ = 0.0;  ///< shown while a hand pushes nothing
  std::array<std::string, 2> tool_kinds_;
  std::vector<std::string> organ_names_;
  int64_t events_seen_ = 0;
  std::deque<Shown> shown_;
  HudState state_;
};

/// "mm:ss" (hours folded into the minutes).
[[nodiscard]] std::string clock_text(double seconds);

}  // namespace lap::app
