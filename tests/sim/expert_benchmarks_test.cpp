// The experts' benchmarks of the shipped scenarios that have them, the introductory one and the
// default patient (sim/authoring/expert_benchmarks.h): the shipped proficiency section is what
// the planner's varied runs give, the expert's own run meets every benchmark, and a clumsy run
// that tears the duct misses the force's.

#include "sim/authoring/expert_benchmarks.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "sim/report/proficiency.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

// Every shipped scenario with a proficiency section: the introductory one and the default
// patient.
TEST(ExpertBenchmarks, TheShippedSectionIsWhatTheVariedExpertRunsGive) {
  if (test::kSanitizerDivisor != 1) {
    GTEST_SKIP() << "twelve sessions, and the sanitizer build's -O1 rounds differently in the "
                    "sixth digit; the optimised build checks the shipped figures";
  }
  for (const char* stem : {"introductory", "default"}) {
    const fs::path file = test::source_dir() / "scenarios" / (std::string(stem) + ".yaml");
    const SceneLoadResult scene = load_scene_file(file);
    ASSERT_TRUE(scene.ok()) << scene.message();
    const Result<ExpertBenchmarks> b = plan_expert_benchmarks(scene.value());
    ASSERT_TRUE(b.ok()) << stem << ": " << b.message();
    EXPECT_EQ(b.value().runs, 12) << stem;
    // How many succeeded is in the section's source, compared below (the default patient's
    // 3 mm duct: one variant's catheter goes through the wall).
    std::printf("[ benchmarks ] %s: %d of 12 succeeded %s\n", stem, b.value().succeeded,
                testing::PrintToString(b.value().failures).c_str());
    const std::string text = file_text(file);
    const size_t at = text.find("\nproficiency:\n");
    ASSERT_NE(at, std::string::npos) << stem;
    EXPECT_EQ(text.substr(at + 1), proficiency_yaml(b.value().spec))
        << "regenerate with laptrainer-cli expert-benchmarks --scenario scenarios/" << stem
        << ".yaml --runs 12";
  }
}

TEST(ExpertBenchmarks, TheExpertMeetsThemAndATearMissesTheForce) {
  const ProficiencySpec& spec = *introductory_scene().scenario.proficiency;
  ASSERT_FALSE(spec.metrics.empty());
  const SessionMetrics expert = run_scripts(introductory_scene(), kScripts, "expert");
  for (const BenchmarkResult& r : assess_proficiency(spec, expert.training)) {
    EXPECT_TRUE(r.met) << r.benchmark.metric << " " << r.value << " vs limit " << r.limit;
  }
  const SessionMetrics tear = run_scripts(introductory_scene(), kScripts, "clumsy_tear");
  const nlohmann::ordered_json j = proficiency_to_json(spec, tear.training);
  EXPECT_EQ(j["metrics"]["max_force_duct_n"]["met"], false) << j.dump();
  EXPECT_EQ(j["metrics"]["time_over_threshold_s"]["met"], false) << j.dump();
  EXPECT_EQ(j["all_met"], false);
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
