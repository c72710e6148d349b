#pragma once
/// \file
/// The shape-perception experiment of thesis §5.5 as a task: a sphere, cone, cylinder or cube,
/// one at a time, at a random orientation (seeded), with no visual display, explored with a point
/// probe (chapter 4) or a ray probe (chapter 5); the participant names the shape as quickly as
/// they can, and the answer and the time to answer are recorded per rendering mode. The results
/// go into a table in the form of the thesis' (Figure 5-16: per shape the mean time to identify
/// it with each probe, and how much faster the ray was; here also how many were named right),
/// exported as CSV.
///
/// The engine only keeps the sequence and the answers: whoever runs it presents each trial's
/// scene (sim/authoring/perception_trials.h builds it: the shape, the probe kind, no display) as
/// a session, calls start_trial() when the participant starts exploring and answer() when they
/// name the shape — the application from its buttons, the tests and `run_scripted_answers` from a
/// script of scripted answers. Times are whatever clock the caller uses, in seconds.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.h"

namespace lap::sim {

/// The four primitive objects of §5.5.
enum class PerceivedShape : uint8_t { kSphere, kCone, kCylinder, kCube };
inline constexpr std::array<PerceivedShape, 4> kPerceivedShapes = {
    PerceivedShape::kSphere, PerceivedShape::kCone, PerceivedShape::kCylinder,
    PerceivedShape::kCube};
/// "sphere", "cone", "cylinder", "cube".
[[nodiscard]] std::string_view to_string(PerceivedShape shape);
[[nodiscard]] std::optional<PerceivedShape> parse_perceived_shape(std::string_view text);

/// The two rendering conditions compared (§5.5): the point-based and the ray-based probe.
enum class ProbeMode : uint8_t { kPoint, kRay };
/// "point", "ray".
[[nodiscard]] std::string_view to_string(ProbeMode mode);
[[nodiscard]] std::optional<ProbeMode> parse_probe_mode(std::string_view text);

struct PerceptionSettings {
  uint32_t seed = 1;        ///< the order and the orientations
  int32_t repetitions = 2;  ///< per shape and mode (the thesis: 76)
  std::vector<ProbeMode> modes = {ProbeMode::kPoint, ProbeMode::kRay};
};

/// One presentation.
struct PerceptionTrial {
  int32_t index = 0;
  PerceivedShape shape = PerceivedShape::kSphere;
  ProbeMode mode = ProbeMode::kPoint;
  int32_t repetition = 0;  ///< 0-based, among this shape's in this mode
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< uniform over rotations
};

/// What the participant did in one trial.
struct PerceptionAnswer {
  PerceptionTrial trial;
  PerceivedShape named = PerceivedShape::kSphere;
  double time_s = 0.0;  ///< from start_trial to answer
  [[nodiscard]] bool correct() const { return named == trial.shape; }
};

class PerceptionExperiment {
 public:
  /// The whole sequence: every shape `repetitions` times in every mode, in a seeded random order
  /// (Fisher–Yates on a Mersenne twister's raw output, the same on every platform), each at a
  /// uniformly random orientation (Shoemake's method). Diagnostics name the bad setting.
  static Result<PerceptionExperiment> create(const PerceptionSettings& settings);

  [[nodiscard]] const std::vector<PerceptionTrial>& trials() const { return trials_; }
  /// The trial to present next, or none when every trial is answered.
  [[nodiscard]] const PerceptionTrial* current() const {
    return next_ < trials_.size() ? &trials_[next_] : nullptr;
  }
  [[nodiscard]] bool done() const { return next_ >= trials_.size(); }
  /// The participant starts exploring the current trial at t_s.
  Status start_trial(double t_s);
  /// The participant names the shape at t_s (after start_trial): recorded, and the next trial
  /// becomes current.
  Status answer(PerceivedShape named, double t_s);
  [[nodiscard]] const std::vector<PerceptionAnswer>& answers() const { return answers_; }

 private:
  std::vector<PerceptionTrial> trials_;
  std::vector<PerceptionAnswer> answers_;
  size_t next_ = 0;
  std::optional<double> started_s_;
};

/// One row of the results: a shape in one mode.
struct PerceptionRow {
  PerceivedShape shape = PerceivedShape::kSphere;
  ProbeMode mode = ProbeMode::kPoint;
  int32_t trials = 0;
  int32_t correct = 0;
  double mean_time_s = 0.0;  ///< over all its answers
  double sd_time_s = 0.0;    ///< sample standard deviation (0 for one answer)
};

/// The thesis' table: per shape and mode, and per shape how much faster the ray was.
struct PerceptionTable {
  std::vector<PerceptionRow> rows;  ///< shapes in kPerceivedShapes' order, point before ray
  /// Per shape: (mean point time − mean ray time) / mean point time × 100; absent without both.
  std::array<std::optional<double>, 4> ray_faster_percent{};
};

[[nodiscard]] PerceptionTable tabulate(const std::vector<PerceptionAnswer>& answers);
/// `shape,mode,trials,correct,percent_correct,mean_time_s,sd_time_s,ray_faster_percent`, one row
/// per shape and mode (ray_faster_percent on the ray's row, empty where not known).
[[nodiscard]] std::string to_csv(const PerceptionTable& table);
/// Every answer, one row per trial in the order presented:
/// `trial,shape,mode,repetition,orientation_w,orientation_x,orientation_y,orientation_z,named,correct,time_s`.
[[nodiscard]] std::string to_csv(const std::vector<PerceptionAnswer>& answers);

/// A scripted participant: for a shape in a mode, its repetition-th presentation is named
/// `named` after `time_s`. CSV rows `shape,mode,repetition,named,time_s` (a header line
/// allowed, `#` comments); errors name the source, line and field.
struct ScriptedAnswer {
  PerceivedShape shape = PerceivedShape::kSphere;
  ProbeMode mode = ProbeMode::kPoint;
  int32_t repetition = 0;
  PerceivedShape named = PerceivedShape::kSphere;
  double time_s = 0.0;
};
[[nodiscard]] Result<std::vector<ScriptedAnswer>> parse_scripted_answers(const std::string& text,
                                                                         const std::string& source);
/// Runs the experiment to its end on the scripted answers (trials back to back from t = 0);
/// a trial without a scripted answer is a problem naming it.
[[nodiscard]] Status run_scripted_answers(PerceptionExperiment* experiment,
                                          const std::vector<ScriptedAnswer>& script);

}  // namespace lap::sim
