#pragma once
/// \file
/// The review's charts over sessions (Qt Charts): a trainee's learning curve for one metric —
/// the metric at each session, the experts' band (mean ± 2 SD) shaded, the proficiency limit
/// dashed, each session's point green where met and red where not — and the cohort's: every
/// trainee's curve of the metric over their own session numbers, against the same band.

#include <QString>
#include <optional>
#include <vector>

#include "app/store/session_table.h"
#include "sim/setup/scenario.h"

class QChart;

namespace lap::app {

/// Fills `chart` (emptied first) with `points` (one trainee's, oldest first) against
/// `benchmark`. Returns the number of sessions drawn.
int draw_learning_curve(QChart* chart, const QString& title, const std::vector<MetricPoint>& points,
                        const std::optional<sim::MetricBenchmark>& benchmark);

/// Fills `chart` with one curve per trainee in `points` (any order; each trainee's sessions
/// numbered from 1 in time order). Returns the number of trainees drawn.
int draw_cohort(QChart* chart, const QString& title, const std::vector<MetricPoint>& points,
                const std::optional<sim::MetricBenchmark>& benchmark);

}  // namespace lap::app
