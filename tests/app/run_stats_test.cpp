// `laptrainer --stats` (app/run_stats.h): the frame rate's mean and 5th percentile from frame
// times, against hand-computed values.

#include "app/run_stats.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace lap::app {
namespace {

// 99 frames 20 ms apart, then one 100 ms late: the mean over the 99 intervals is
// 99 / (98 · 0.02 + 0.1) = 48.06 frames/s; 95 % of the intervals are 20 ms: p5 50 frames/s.
TEST(RunStats, FrameRatesFromFrameTimes) {
  const sim::SessionMetrics none;
  std::vector<double> t;
  for (int k = 0; k < 99; ++k) t.push_back(10.0 + 0.02 * k);
  t.push_back(t.back() + 0.1);
  const nlohmann::ordered_json j = run_stats_json(t, 1.25, none);
  EXPECT_NEAR(j["graphics"]["fps_mean"].get<double>(), 99.0 / (98 * 0.02 + 0.1), 1e-9);
  EXPECT_NEAR(j["graphics"]["fps_p5"].get<double>(), 50.0, 1e-6);
  EXPECT_EQ(j["graphics"]["frames"], 100);
  EXPECT_DOUBLE_EQ(j["graphics"]["first_frame_s"].get<double>(), 1.25);
  for (const char* key : {"rate_hz", "lateness_p999_us", "missed_deadlines"}) {
    EXPECT_TRUE(j["haptic"].contains(key)) << key;
  }
  EXPECT_TRUE(j["model"].contains("rate_hz"));
  // Half the frames late: the 5th percentile falls to the slow ones.
  std::vector<double> slow = {0.0};
  for (int k = 0; k < 20; ++k) slow.push_back(slow.back() + (k % 2 == 0 ? 0.01 : 0.05));
  EXPECT_NEAR(run_stats_json(slow, 0.0, none)["graphics"]["fps_p5"].get<double>(), 20.0, 1e-6);
  EXPECT_TRUE(run_stats_json({}, -1.0, none)["graphics"]["fps_mean"].is_null());
}

}  // namespace
}  // namespace lap::app
