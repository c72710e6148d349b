// The command-line contracts in ARCHITECTURE.md, exercised on the built binaries.

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace lap::test {
namespace {

std::string cli() { return (bin_dir() / "laptrainer-cli").string(); }
std::string app() { return (bin_dir() / "laptrainer").string(); }

TEST(CliValidate, DefaultScenarioIsOk) {
  const CommandResult r = run_command(cli() + " validate --scenario " +
                                      (source_dir() / "scenarios/default.yaml").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(": ok"), std::string::npos);
}

TEST(CliValidate, ProblemsGoToStderrAsFileLineFieldAndExitTwo) {
  TempDir dir;
  const auto f = dir.write("s.yaml",
                           "version: 1\nname: x\norgans:\n  - name: a\n    mesh: none.obj\n"
                           "    material: {stiffness_n_per_m: -1}\n");
  const CommandResult r = run_command(cli() + " validate --scenario " + f.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(f.string() + ":5: organs[0].mesh: file 'none.obj' not found"),
            std::string::npos)
      << r.err;
  EXPECT_NE(
      r.err.find(f.string() +
                 ":6: organs[0].material.stiffness_n_per_m: expected a positive number, got '-1'"),
      std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("2 problems found"), std::string::npos);
}

TEST(CliValidate, UsageErrors) {
  EXPECT_EQ(run_command(cli() + " validate").exit_code, 64);
  EXPECT_EQ(run_command(cli() + " validate --scenario a.yaml --bogus 1").exit_code, 64);
  EXPECT_EQ(run_command(cli() + " frobnicate").exit_code, 64);
}

TEST(CliMeshInfo, DiagnosesAndRepairs) {
  TempDir dir;
  const auto f =
      dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
  CommandResult r = run_command(cli() + " mesh-info --mesh " + f.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.out.find("3 boundary edges"), std::string::npos) << r.out;
  r = run_command(cli() + " mesh-info --mesh " + f.string() + " --repair --out " +
                  (dir.path() / "fixed.obj").string());
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("closed 1 holes"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "fixed.obj"));
}

TEST(AppHeadless, WithoutADisplayItSaysSoAndRunsTheDefaultScenario) {
  const CommandResult r = run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + app());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("no display available"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("organs: 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("headless run finished"), std::string::npos) << r.out;
}

TEST(AppHeadless, ScreenshotWithoutADisplayIsAClearError) {
  const CommandResult r =
      run_command("env -u DISPLAY " + app() + " --screenshot /tmp/x.png --frames 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--screenshot needs a display"), std::string::npos) << r.err;
}

TEST(AppHeadless, BadArgumentsAreUsageErrors) {
  EXPECT_EQ(run_command(app() + " --frames zero").exit_code, 64);
  EXPECT_EQ(run_command(app() + " --what").exit_code, 64);
}

TEST(AppHeadless, BadScenarioIsReportedNotCrashed) {
  TempDir dir;
  const auto f = dir.write("s.yaml", "version: 3\n");
  const CommandResult r = run_command("env -u DISPLAY " + app() + " --scenario " + f.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(f.string() + ":1: version: expected a whole number from 1 to 1, got '3'"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace lap::test
