// The experts' benchmarks of the default scenario (sim/authoring/expert_benchmarks.h): the
// shipped proficiency section is what the planner's varied runs give, the expert's own run meets
// every benchmark, and a clumsy run that tears the duct misses the force's.

#include "sim/authoring/expert_benchmarks.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "sim/report/proficiency.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/default";

TEST(ExpertBenchmarks, TheShippedSectionIsWhatTheVariedExpertRunsGive) {
  if (test::kSanitizerDivisor != 1) {
    GTEST_SKIP() << "twelve sessions, and the sanitizer build's -O1 rounds differently in the "
                    "sixth digit; the optimised build checks the shipped figures";
  }
  const Result<ExpertBenchmarks> b = plan_expert_benchmarks(default_scene());
  ASSERT_TRUE(b.ok()) << b.message();
  EXPECT_EQ(b.value().runs, 12);
  EXPECT_EQ(b.value().succeeded, 12) << testing::PrintToString(b.value().failures);
  const std::string text = file_text(test::source_dir() / "scenarios/default.yaml");
  const size_t at = text.find("\nproficiency:\n");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(text.substr(at + 1), proficiency_yaml(b.value().spec))
      << "regenerate with laptrainer-cli expert-benchmarks --scenario scenarios/default.yaml "
         "--runs 12";
}

TEST(ExpertBenchmarks, TheExpertMeetsThemAndATearMissesTheForce) {
  const ProficiencySpec& spec = *default_scene().scenario.proficiency;
  ASSERT_FALSE(spec.metrics.empty());
  const SessionMetrics expert = run_scripts(default_scene(), kScripts, "expert");
  for (const BenchmarkResult& r : assess_proficiency(spec, expert.training)) {
    EXPECT_TRUE(r.met) << r.benchmark.metric << " " << r.value << " vs limit " << r.limit;
  }
  const SessionMetrics tear = run_scripts(default_scene(), kScripts, "clumsy_tear");
  const nlohmann::ordered_json j = proficiency_to_json(spec, tear.training);
  EXPECT_EQ(j["metrics"]["max_force_duct_n"]["met"], false) << j.dump();
  EXPECT_EQ(j["metrics"]["time_over_threshold_s"]["met"], false) << j.dump();
  EXPECT_EQ(j["all_met"], false);
}

// Fewer than two runs that succeed give no spread to benchmark.
TEST(ExpertBenchmarks, NeedTwoRunsThatSucceed) {
  ExpertBenchmarkSettings one;
  one.runs = 1;
  const Result<ExpertBenchmarks> b = plan_expert_benchmarks(default_scene(), one);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.message().find("fewer than two of the 1 expert runs succeed"), std::string::npos)
      << b.message();
}

}  // namespace
}  // namespace lap::sim
