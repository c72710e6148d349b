#pragma once
/// \file
/// `laptrainer --stats FILE`: how fast the three loops ran, written at exit as JSON
/// (docs/architecture.md): {"graphics": {"fps_mean", "fps_p5", "frames", "first_frame_s"},
/// "haptic": {"rate_hz", "lateness_p999_us", "missed_deadlines", "late_ticks"},
/// "model": {"rate_hz"}}. fps_p5 is the frame rate that 95 % of the frames beat (1 / the 95th
/// percentile of the intervals between frames); first_frame_s the time from the process's start
/// to its first frame.

#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "sim/runtime/session.h"

namespace lap::app {

/// From the frames' end times [s, any origin, increasing], the start-to-first-frame time [s]
/// and the session's metrics (its loop statistics).
[[nodiscard]] nlohmann::ordered_json run_stats_json(const std::vector<double>& frame_times_s,
                                                    double first_frame_s,
                                                    const sim::SessionMetrics& session);

}  // namespace lap::app
