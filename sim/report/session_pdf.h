#pragma once
/// \file
/// A session's report as a PDF for the instructor (`laptrainer-cli report --format pdf`): page
/// one the result, its reasons, the phase times and three plots over the session's time — the
/// force on the duct with its injury threshold, the insertion depth with its target, both tools'
/// speeds — with the task's events marked on each; page two every training metric with the
/// scenario's proficiency verdict where it has one, and the events listed.

#include <string>
#include <vector>

#include "sim/report/pdf_document.h"
#include "sim/runtime/session.h"

namespace lap::sim {

/// What the report says beside the session's metrics.
struct SessionPdfContext {
  std::string scenario_name;
  std::string scenario_file;
  std::string session;               ///< the recording's folder
  std::string mode;                  ///< "fast" or "realtime"
  double duct_injury_force_n = 0.0;  ///< 0: none drawn
  double insertion_depth_m = 0.0;    ///< 0: none drawn
  std::vector<std::string> notes;
};

[[nodiscard]] PdfDocument session_pdf(const SessionMetrics& m, const SessionPdfContext& context);

}  // namespace lap::sim
