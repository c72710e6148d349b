// The experts' benchmarks of the shipped scenarios that have them, the introductory one and the
// default patient (sim/authoring/expert_benchmarks.h): the shipped proficiency section is what
// the planner's varied runs give, the expert's own run meets every benchmark, and a clumsy run
// that tears the duct misses the force's.

#include "sim/authoring/expert_benchmarks.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "sim/report/proficiency.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

// A shipped scenario with a proficiency section: `stem`'s section is what the command writes,
// with `succeeded` of its 12 varied runs succeeding and each of the others failing with
// `failure` (the default patient's 3 mm duct: one variant's catheter goes through the wall).
void expect_shipped_section(const std::string& stem, int succeeded, const std::string& failure) {
  SCOPED_TRACE(stem);
  const fs::path file = test::source_dir() / "scenarios" / (stem + ".yaml");
  const SceneLoadResult scene = load_scene_file(file);
  ASSERT_TRUE(scene.ok()) << scene.message();
  const Result<ExpertBenchmarks> b = plan_expert_benchmarks(scene.value());
  ASSERT_TRUE(b.ok()) << b.message();
  EXPECT_EQ(b.value().runs, 12);
  EXPECT_EQ(b.value().succeeded, succeeded) << testing::PrintToString(b.value().failures);
  for (const std::string& f : b.value().failures) {
    EXPECT_NE(f.find(failure), std::string::npos) << f;
  }
  const std::string text = file_text(file);
  const size_t at = text.find("\nproficiency:\n");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(text.substr(at + 1), proficiency_yaml(b.value().spec))
      << "regenerate with laptrainer-cli expert-benchmarks --scenario scenarios/" << stem
      << ".yaml --runs 12";
}

TEST(ExpertBenchmarks, TheShippedSectionsAreWhatTheVariedExpertRunsGive) {
  if (test::kSanitizerDivisor != 1) {
    GTEST_SKIP() << "twelve sessions each, and the sanitizer build's -O1 rounds differently in "
                    "the sixth digit; the optimised build checks the shipped figures";
  }
  expect_shipped_section("introductory", 12, "");
  expect_shipped_section("default", 11, "failure: wall_perforation");
}

// The expert's own run meets every benchmark of its scenario, and the clumsy run that tears the
// duct misses the force's.
void expect_expert_meets_them(const std::string& stem) {
  SCOPED_TRACE(stem);
  const SceneLoadResult scene =
      load_scene_file(test::source_dir() / "scenarios" / (stem + ".yaml"));
  ASSERT_TRUE(scene.ok()) << scene.message();
  ASSERT_TRUE(scene.value().scenario.proficiency.has_value());
  const ProficiencySpec& spec = *scene.value().scenario.proficiency;
  ASSERT_FALSE(spec.metrics.empty());
  const fs::path scripts = test::source_dir() / "scenarios/scripts" / stem;
  const SessionMetrics expert = run_scripts(scene.value(), scripts, "expert");
  for (const BenchmarkResult& r : assess_proficiency(spec, expert.training)) {
    EXPECT_TRUE(r.met) << r.benchmark.metric << " " << r.value << " vs limit " << r.limit;
  }
  const SessionMetrics tear = run_scripts(scene.value(), scripts, "clumsy_tear");
  const nlohmann::ordered_json j = proficiency_to_json(spec, tear.training);
  EXPECT_EQ(j["metrics"]["max_force_duct_n"]["met"], false) << j.dump();
  EXPECT_EQ(j["metrics"]["time_over_threshold_s"]["met"], false) << j.dump();
  EXPECT_EQ(j["all_met"], false);
}

TEST(ExpertBenchmarks, TheExpertMeetsThemAndATearMissesTheForce) {
  expect_expert_meets_them("introductory");
  expect_expert_meets_them("default");
}

// Fewer than two runs that succeed give no spread to benchmark.
TEST(ExpertBenchmarks, NeedTwoRunsThatSucceed) {
  ExpertBenchmarkSettings one;
  one.runs = 1;
  const Result<ExpertBenchmarks> b = plan_expert_benchmarks(introductory_scene(), one);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.message().find("fewer than two of the 1 expert runs succeed"), std::string::npos)
      << b.message();
}

}  // namespace
}  // namespace lap::sim
