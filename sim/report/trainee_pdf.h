#pragma once
/// \file
/// A trainee's report as a PDF for the instructor (the review's "PDF per trainee"): page one who,
/// which scenario, the sessions in time order (date, result and reasons, completion time) and
/// where the trainee stands against proficiency (proficiency_progress.h); then one learning curve
/// per benchmarked metric — the metric over the sessions with the experts' band (mean ± 2 SD)
/// shaded and the limit drawn, each session's point green where met, red where not — three to a
/// page. Metrics without a benchmark follow as curves without a band. Page one also has a table
/// of where the trainee stands on each benchmark (limit, latest value, met per session).

#include <optional>
#include <string>
#include <vector>

#include "sim/report/pdf_document.h"
#include "sim/report/proficiency_progress.h"

namespace lap::sim {

/// One of the trainee's sessions, as the report lists it.
struct TraineeSessionLine {
  std::string started;  ///< as shown (local time, minutes)
  std::string result;   ///< success | failure | incomplete
  std::vector<std::string> reasons;
  double completion_time_s = 0.0;  ///< NaN: none
  bool interrupted = false;
};

/// A metric over the trainee's sessions (oldest first), with its benchmark when it has one.
struct LearningCurve {
  std::string metric;
  std::vector<double> values;  ///< per session (NaN: undefined there)
  std::optional<ProficiencyProgress> progress;
};

struct TraineePdfContext {
  std::string trainee;
  std::string scenario_name;
  std::string scenario_file;
  std::string proficiency_source;            ///< where the experts' figures come from ("" : none)
  std::vector<TraineeSessionLine> sessions;  ///< oldest first
  std::vector<LearningCurve> curves;
  std::vector<std::string> notes;
};

[[nodiscard]] PdfDocument trainee_pdf(const TraineePdfContext& context);

}  // namespace lap::sim
