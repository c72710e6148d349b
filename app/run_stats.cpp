#include "app/run_stats.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace lap::app {

nlohmann::ordered_json run_stats_json(const std::vector<double>& t, double first_frame_s,
                                      const sim::SessionMetrics& session) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json g;
  g["frames"] = t.size();
  if (t.size() >= 2) {
    g["fps_mean"] = static_cast<double>(t.size() - 1) / (t.back() - t.front());
    std::vector<double> gaps;
    for (size_t i = 1; i < t.size(); ++i) gaps.push_back(t[i] - t[i - 1]);
    // The 95th percentile of the intervals (nearest rank): 95 % of the frames came sooner.
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(gaps.size()))) - 1;
    std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(rank), gaps.end());
    g["fps_p5"] = gaps[rank] > 0.0 ? 1.0 / gaps[rank] : 0.0;
  } else {
    g["fps_mean"] = nullptr;
    g["fps_p5"] = nullptr;
  }
  g["first_frame_s"] = first_frame_s >= 0.0 ? nlohmann::ordered_json(first_frame_s) : nullptr;
  j["graphics"] = g;
  j["haptic"] = {{"rate_hz", session.haptic.achieved_rate_hz()},
                 {"lateness_p999_us", session.haptic.jitter_quantile_s(0.999) * 1e6},
                 {"missed_deadlines", session.haptic.missed_deadlines()},
                 {"late_ticks", session.late_ticks}};
  j["model"] = {{"rate_hz", session.model.achieved_rate_hz()}};
  return j;
}

}  // namespace lap::app
