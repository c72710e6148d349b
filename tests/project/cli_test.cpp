// The command-line contracts in docs/architecture.md, exercised on the built binaries.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "sim/report/recorded_frames.h"
#include "sim/report/recording_reader.h"
#include "sim/runtime/perception_experiment.h"
#include "sim/setup/content_digest.h"
#include "tests/support/small_disk.h"
#include "tests/test_support.h"

namespace lap::test {
namespace {

std::string cli() { return (bin_dir() / "laptrainer-cli").string(); }
std::string app() { return (bin_dir() / "laptrainer").string(); }

// The cells of one CSV row.
std::vector<std::string> csv_cells(const std::string& line) {
  std::stringstream ss(line);
  std::vector<std::string> c;
  for (std::string cell; std::getline(ss, cell, ',');) c.push_back(cell);
  return c;
}

TEST(CliValidate, EveryShippedScenarioIsOk) {
  int checked = 0;
  for (const auto& e : std::filesystem::directory_iterator(source_dir() / "scenarios")) {
    if (e.path().extension() != ".yaml") continue;
    ++checked;
    const CommandResult r = run_command(cli() + " validate --scenario " + e.path().string());
    EXPECT_EQ(r.exit_code, 0) << e.path() << ": " << r.err;
    EXPECT_NE(r.out.find(": ok"), std::string::npos) << e.path();
  }
  EXPECT_GE(checked, 5);  // introductory, default and the three graded patients
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

// A 10 cm cube centred at the origin, as OBJ.
constexpr const char* kBoxObj =
    "v -0.05 -0.05 -0.05\nv 0.05 -0.05 -0.05\nv 0.05 0.05 -0.05\nv -0.05 0.05 -0.05\n"
    "v -0.05 -0.05 0.05\nv 0.05 -0.05 0.05\nv 0.05 0.05 0.05\nv -0.05 0.05 0.05\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(CliProbe, PointProbeAgainstABoxGivesStiffnessTimesDepth) {
  TempDir dir;
  // The path comes down onto the top face.
  const auto mesh = dir.write("box.obj", kBoxObj);
  std::string path = "x,y,z\n";
  for (int i = 0; i <= 20; ++i)
    path += "0.01,0.0" + std::to_string(60 - i) + ",0.02\n";  // 60 -> 40 mm
  const auto csv = dir.write("path.csv", path);
  const auto out = dir.path() / "out.csv";
  const CommandResult r =
      run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string() +
                  " --probe point --stiffness 400 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "tick,ihip_x,ihip_y,ihip_z,force_x,force_y,force_z,contact_kind,primitive_id,step_ns");
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), 10U) << line;
    const double hip_y = 0.060 - 0.001 * rows;
    const double depth = std::max(0.0, 0.05 - hip_y);
    // The OBJ reader stores 0.05 as a float (0.0500000007): about 3e-7 N at 400 N/m.
    EXPECT_NEAR(std::stod(c[5]), 400.0 * depth, 1e-6) << line;
    EXPECT_EQ(c[7], depth > 0.0 ? "face" : (hip_y == 0.05 ? c[7] : "none")) << line;
    EXPECT_GE(std::stoll(c[9]), 0);
    ++rows;
  }
  EXPECT_EQ(rows, 21);
}

// The passive response (haptics/segment_proxy.h, "Response") is a spring of k at each end between
// the ideal and the virtual rod: lying flat, both ends are pressed by the depth, two springs in
// parallel, 2 k d.
TEST(CliProbe, SegmentProbeLyingOnABoxFaceGivesTwiceStiffnessTimesDepth) {
  TempDir dir;
  const auto mesh = dir.write("box.obj", kBoxObj);
  // A 6 cm rod lying along x, lowered from 60 to 40 mm onto the top face (y = 50 mm).
  std::string path = "x1,y1,z1,x2,y2,z2\n";
  for (int i = 0; i <= 20; ++i) {
    const std::string y = "0.0" + std::to_string(60 - i);
    path += "-0.03," + y + ",0.01,0.03," + y + ",0.01\n";
  }
  const auto csv = dir.write("path.csv", path);
  const auto out = dir.path() / "out.csv";
  const CommandResult r =
      run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string() +
                  " --probe segment --stiffness 400 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "tick,ideal_a_x,ideal_a_y,ideal_a_z,ideal_b_x,ideal_b_y,ideal_b_z,force_x,force_y,"
            "force_z,torque_x,torque_y,torque_z,contact_type,primitive_kind,primitive_id,step_ns");
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), 17U) << line;
    const double y = 0.060 - 0.001 * rows;
    const double depth = std::max(0.0, 0.05 - y);
    EXPECT_NEAR(std::stod(c[8]), 2.0 * 400.0 * depth, 1e-5) << line;
    if (depth > 0.0) {
      EXPECT_EQ(c[13], "segment-face") << line;
      EXPECT_NEAR(std::stod(c[2]), 0.05, 2e-6) << line;  // the ideal rod lies on the face
    }
    ++rows;
  }
  EXPECT_EQ(rows, 21);
}

// An open mesh is a thin, two-sided surface for the segment probe too: a rod lifted into a
// square plate (y = 0, normal +y) from below is pushed back down.
TEST(CliProbe, SegmentProbeAcceptsAnOpenMeshAndFeelsItFromBelow) {
  TempDir dir;
  const auto mesh = dir.write("plate.obj",
                              "v -0.05 0 -0.05\nv 0.05 0 -0.05\nv 0.05 0 0.05\nv -0.05 0 0.05\n"
                              "f 1 3 2\nf 1 4 3\n");
  std::string path = "x1,y1,z1,x2,y2,z2\n";
  // From 10.5 mm below to 9.5 mm above, in 1 mm steps (a rod exactly on the plane of a
  // two-sided surface has no side to be held on).
  for (int i = 0; i <= 20; ++i) {
    const double y = -0.0105 + 0.001 * i;
    path += "-0.02," + std::to_string(y) + ",0.01,0.02," + std::to_string(y) + ",0.01\n";
  }
  const auto csv = dir.write("path.csv", path);
  const auto out = dir.path() / "out.csv";
  const CommandResult r =
      run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string() +
                  " --probe segment --stiffness 400 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), 17U) << line;
    const double y = -0.0105 + 0.001 * rows;
    // Held below the plate: the force pushes down by k at each end times how far above it the
    // rod is.
    EXPECT_NEAR(std::stod(c[8]), -2.0 * 400.0 * std::max(0.0, y), 1e-5) << line;
    EXPECT_LE(std::stod(c[2]), 2e-6) << "the ideal rod stays below the plate: " << line;
    ++rows;
  }
  EXPECT_EQ(rows, 21);
}

TEST(CliProbe, BadPathRowsAreNamedByLine) {
  TempDir dir;
  const auto mesh = dir.write(
      "t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const auto csv = dir.write("p.csv", "0,0,0\n0.1,0.2\n");
  const CommandResult r =
      run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(csv.string() + ":2: expected 3 numbers x,y,z in metres, got '0.1,0.2'"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string() +
                        " --probe ray")
                .exit_code,
            64);
  EXPECT_EQ(run_command(cli() + " probe --mesh " + mesh.string() + " --path " + csv.string() +
                        " --stiffness -3")
                .exit_code,
            64);
}

// The first value named `key` in the JSON text, depth first in the order written, as JSON text
// (a string with its quotes); "" when the text is not JSON or has no such key.
std::string json_field(const nlohmann::ordered_json& j, const std::string& key) {
  if (!j.is_object() && !j.is_array()) return {};
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (j.is_object() && it.key() == key) return it.value().dump();
    const std::string inner = json_field(it.value(), key);
    if (!inner.empty()) return inner;
  }
  return {};
}
std::string json_field(const std::string& json, const std::string& key) {
  const auto j = nlohmann::ordered_json::parse(json, nullptr, /*allow_exceptions=*/false);
  return j.is_discarded() ? std::string() : json_field(j, key);
}

TEST(CliRun, ScriptedFastRunPrintsMetricsAndItsReplayMatchesBitForBit) {
  TempDir dir;
  // Handles in front of the introductory scenario's ports (left x -0.07, right 0.06; y 0.03,
  // z 0.18), pushed 3 cm deeper over 0.3 s while the jaws close.
  const auto left = dir.write("left.csv",
                              "time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad\n"
                              "0.0,-0.07,0.03,0.40,1,0,0,0,0.8\n"
                              "0.3,-0.06,0.03,0.37,1,0,0,0,0.2\n");
  const auto right = dir.write("right.csv",
                               "0.0,0.06,0.03,0.40,1,0,0,0,0.8\n"
                               "0.3,0.05,0.04,0.37,1,0,0,0,0.2\n");
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const std::string rec = (dir.path() / "rec").string();
  const CommandResult r =
      run_command(cli() + " run --scenario " + scenario + " --left scripted:" + left.string() +
                  " --right scripted:" + right.string() + " --duration 1 --fast --record " + rec);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json_field(r.out, "mode"), "\"fast\"");
  EXPECT_EQ(json_field(r.out, "ticks"), "302");  // the scripts end at 0.3 s
  EXPECT_EQ(json_field(r.out, "paused"), "false");
  EXPECT_EQ(json_field(r.out, "recorded_ticks"), "302");
  // The metrics are kept beside the inputs, with the series for plots.
  std::ifstream metrics(rec + "/metrics.json");
  auto saved = nlohmann::ordered_json::parse(metrics, nullptr, false);
  ASSERT_TRUE(saved.contains("series"));
  saved.erase("series");
  EXPECT_EQ(saved, nlohmann::ordered_json::parse(r.out, nullptr, false));
  const std::string hash = json_field(r.out, "state_hash");
  ASSERT_EQ(hash.size(), 18U) << r.out;
  const CommandResult replay =
      run_command(cli() + " run --scenario " + scenario + " --left replay:" + rec +
                  "/left.lapdev --right replay:" + rec + "/right.lapdev --duration 1 --fast");
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_EQ(json_field(replay.out, "state_hash"), hash);
  // The task is scored the same on the replay.
  EXPECT_FALSE(json_field(r.out, "task").empty());
  EXPECT_EQ(json_field(replay.out, "task"), json_field(r.out, "task"));
}

// The introductory scenario rewritten into a temporary folder (its meshes by a path from there: a
// scenario names no absolute path), with `edit` applied to its text.
std::filesystem::path introductory_scenario_copy(const TempDir& dir,
                                                 const std::function<void(std::string&)>& edit) {
  std::string text = read_file(source_dir() / "scenarios/introductory.yaml");
  const std::string assets =
      std::filesystem::relative(std::filesystem::absolute(source_dir() / "assets"),
                                std::filesystem::absolute(dir.path()))
          .string();
  for (size_t at = 0; (at = text.find("../assets", at)) != std::string::npos;) {
    text.replace(at, 9, assets);
    at += assets.size();
  }
  edit(text);
  return dir.write("scenario.yaml", text);
}

// The top-level "task" object of `run` (docs/architecture.md): result, reasons, events with
// t_s and kind, completion_time_s.
void expect_task_contract(const nlohmann::ordered_json& task) {
  ASSERT_TRUE(task.is_object()) << task.dump();
  for (const char* key : {"result", "reasons", "events", "completion_time_s"}) {
    ASSERT_TRUE(task.contains(key)) << key << " missing: " << task.dump();
  }
  ASSERT_TRUE(task.at("result").is_string());
  const std::string result = task.at("result");
  EXPECT_TRUE(result == "success" || result == "failure" || result == "incomplete") << result;
  ASSERT_TRUE(task.at("reasons").is_array());
  ASSERT_TRUE(task.at("events").is_array());
  for (const auto& e : task.at("events")) {
    EXPECT_TRUE(e.contains("t_s") && e.at("t_s").is_number()) << e.dump();
    EXPECT_TRUE(e.contains("kind") && e.at("kind").is_string()) << e.dump();
  }
  const auto& done = task.at("completion_time_s");
  EXPECT_TRUE(done.is_null() || done.is_number()) << done.dump();
}

TEST(CliRun, TheTaskObjectFollowsTheContract) {
  TempDir dir;
  // Scripts that last 3 s, the tools held in front of their ports.
  const auto left = dir.write("left.csv",
                              "time_s,x_m,y_m,z_m,qw,qx,qy,qz,gripper_rad\n"
                              "0.0,-0.07,0.03,0.40,1,0,0,0,0.8\n"
                              "3.0,-0.07,0.03,0.40,1,0,0,0,0.8\n");
  const auto right = dir.write("right.csv",
                               "0.0,0.06,0.03,0.40,1,0,0,0,0.8\n"
                               "3.0,0.06,0.03,0.40,1,0,0,0,0.8\n");
  const std::string devices =
      " --left scripted:" + left.string() + " --right scripted:" + right.string() + " --fast";
  auto run = [&](const std::filesystem::path& scenario, double duration) {
    const CommandResult r = run_command(cli() + " run --scenario " + scenario.string() + devices +
                                        " --duration " + std::to_string(duration));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::ordered_json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  };

  // Nothing happens within half a second: incomplete, no reasons, no completion time.
  auto plain = run(source_dir() / "scenarios/introductory.yaml", 0.5);
  ASSERT_FALSE(plain.is_discarded());
  expect_task_contract(plain["task"]);
  EXPECT_EQ(plain["task"]["kind"], "catheter-insertion");
  EXPECT_EQ(plain["task"]["result"], "incomplete");
  EXPECT_TRUE(plain["task"]["reasons"].empty());
  EXPECT_TRUE(plain["task"]["completion_time_s"].is_null());
  EXPECT_EQ(plain["haptic"]["ticks"], 500);

  // A one-second time limit: the task fails at 1 s and the session ends there, not at 3 s.
  auto limited = run(introductory_scenario_copy(dir,
                                                [](std::string& t) {
                                                  const size_t at = t.find("time_limit_s: 600");
                                                  ASSERT_NE(at, std::string::npos);
                                                  t.replace(at, 17, "time_limit_s: 1");
                                                }),
                     3.0);
  ASSERT_FALSE(limited.is_discarded());
  auto& task = limited["task"];
  expect_task_contract(task);
  EXPECT_EQ(task["result"], "failure");
  EXPECT_EQ(task["reasons"], nlohmann::ordered_json::array({"time_limit"}));
  ASSERT_EQ(task["events"].size(), 2U) << task.dump();
  EXPECT_EQ(task["events"][0]["kind"], "time_limit");
  EXPECT_EQ(task["events"][1]["kind"], "failure");
  EXPECT_DOUBLE_EQ(task["events"][1]["t_s"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(task["completion_time_s"].get<double>(), 1.0);
  // The modelling step at tick 1000 ends it; the loop stops before the next tick.
  EXPECT_EQ(limited["haptic"]["ticks"], 1001);

  // Without a task: nothing watched, said so.
  auto free = run(introductory_scenario_copy(dir,
                                             [](std::string& t) {
                                               const size_t at = t.find("\ntask:");
                                               ASSERT_NE(at, std::string::npos);
                                               t.erase(at + 1);
                                             }),
                  0.5);
  ASSERT_FALSE(free.is_discarded());
  expect_task_contract(free["task"]);
  EXPECT_EQ(free["task"]["kind"], "none");
  EXPECT_EQ(free["task"]["result"], "incomplete");
  EXPECT_TRUE(free["task"]["reasons"].empty());
  EXPECT_TRUE(free["task"]["events"].empty());
  EXPECT_TRUE(free["task"]["completion_time_s"].is_null());
}

TEST(CliRun, TheShippedExpertRunEndsInSuccessAndTheSessionWithIt) {
  // The contract's outside check: the expert's scripts for the default scenario, --fast, a long
  // --duration: "success", no reasons, the completion time, and the session ended there.
  const std::filesystem::path scripts = source_dir() / "scenarios/scripts/default";
  const CommandResult r = run_command(
      cli() + " run --scenario " + (source_dir() / "scenarios/default.yaml").string() +
      " --left scripted:" + (scripts / "expert_left.csv").string() +
      " --right scripted:" + (scripts / "expert_right.csv").string() + " --fast --duration 120");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto out = nlohmann::ordered_json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(out.is_discarded()) << r.out;
  const auto& task = out["task"];
  expect_task_contract(task);
  EXPECT_EQ(task["result"], "success") << task.dump();
  EXPECT_TRUE(task["reasons"].empty());
  const double done = task["completion_time_s"].get<double>();
  EXPECT_GT(done, 10.0);
  EXPECT_LT(done, 20.0);
  EXPECT_EQ(task["events"].back()["kind"], "success");
  EXPECT_LE(out["haptic"]["ticks"].get<int64_t>(), static_cast<int64_t>(done * 1000.0) + 1);
  // The "metrics" object: numbers (null where undefined), snake_case names, the contract's keys.
  const auto& metrics = out["metrics"];
  ASSERT_TRUE(metrics.is_object()) << out.dump();
  for (const auto& [name, value] : metrics.items()) {
    EXPECT_TRUE(value.is_number() || value.is_null()) << name;
    EXPECT_EQ(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_"), std::string::npos)
        << name;
  }
  for (const char* key : {"completion_time_s", "path_length_left_m", "path_length_right_m",
                          "max_force_duct_n", "time_over_threshold_s", "catheter_drops"}) {
    EXPECT_TRUE(metrics.contains(key) && metrics[key].is_number()) << key;
  }
  EXPECT_EQ(metrics["completion_time_s"].get<double>(), done);
  EXPECT_EQ(metrics["catheter_drops"], 0.0);
}

// A recorded run on a disk that fills up (a 1 MB tmpfs of the test's own, the kernel's ENOSPC:
// tests/support/small_disk.h): the session runs to its end and prints its result; the streamed
// recording stops where the disk filled and says so; each file that could not be written at the
// end is named and left out whole (no cut-off file); the exit code is 3 (README.md); and `report`
// replays the session from what was kept, up to its last recorded tick. Skipped, saying why,
// where no such disk can be mounted.
TEST(CliRun, ADiskThatFillsUpKeepsWhatWasRecordedAndNamesWhatWasNot) {
  const TempDir dir;
  const std::filesystem::path disk = dir.path() / "disk";
  std::filesystem::create_directory(disk);
  const std::filesystem::path rec = disk / "s1";
  const std::filesystem::path scripts = source_dir() / "scenarios/scripts/introductory";
  const SmallDiskRun small = run_on_a_small_disk(disk, 1024U * 1024U, [&] {
    const CommandResult run = run_command(
        cli() + " run --scenario " + (source_dir() / "scenarios/introductory.yaml").string() +
        " --left scripted:" + (scripts / "expert_left.csv").string() + " --right scripted:" +
        (scripts / "expert_right.csv").string() + " --fast --duration 30 --record " + rec.string());
    const CommandResult report = run_command(cli() + " report --session " + rec.string());
    std::ofstream(dir.path() / "run.out") << run.out;
    std::ofstream(dir.path() / "run.err") << run.err;
    std::ofstream(dir.path() / "report.out") << report.out;
    std::ofstream(dir.path() / "report.err") << report.err;
    std::ofstream files(dir.path() / "files.txt");
    for (const auto& e : std::filesystem::directory_iterator(rec)) {
      files << e.path().filename().string() << "\n";
    }
    std::ofstream(dir.path() / "codes.txt") << run.exit_code << " " << report.exit_code << "\n";
    return 0;
  });
  if (!small.ran) GTEST_SKIP() << "no small disk could be mounted here: " << small.why_not;
  ASSERT_EQ(small.exit_code, 0);
  std::istringstream codes(read_file(dir.path() / "codes.txt"));
  int run_code = -1, report_code = -1;
  codes >> run_code >> report_code;
  const std::string err = read_file(dir.path() / "run.err");
  EXPECT_EQ(run_code, 3) << err;
  // The result, printed whatever became of the recording.
  const auto out = nlohmann::ordered_json::parse(read_file(dir.path() / "run.out"), nullptr, false);
  ASSERT_FALSE(out.is_discarded()) << read_file(dir.path() / "run.out");
  EXPECT_EQ(out["task"]["result"], "success");
  const std::string no_space = std::strerror(ENOSPC);
  EXPECT_NE(
      err.find("warning: the recording " + (rec / "session.lrec").string() + " stopped after "),
      std::string::npos)
      << err;
  for (const char* file : {"left.lapdev", "right.lapdev", "metrics.json"}) {
    EXPECT_NE(err.find((rec / file).string() + ": cannot write the "), std::string::npos) << err;
  }
  EXPECT_NE(err.find(no_space + " (nothing of it was written)"), std::string::npos) << err;
  EXPECT_NE(err.find("the session ran, but not all of its recording was written (above); what "
                     "was written in " +
                     rec.string() + " is kept"),
            std::string::npos)
      << err;
  std::vector<std::string> files = lines_of(read_file(dir.path() / "files.txt"));
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"session.json", "session.lrec"}));
  // What was kept replays, as far as it goes.
  EXPECT_EQ(report_code, 0) << read_file(dir.path() / "report.err");
  EXPECT_NE(read_file(dir.path() / "report.err").find("replayed up to its last recorded tick"),
            std::string::npos)
      << read_file(dir.path() / "report.err");
  const auto replayed =
      nlohmann::ordered_json::parse(read_file(dir.path() / "report.out"), nullptr, false);
  ASSERT_FALSE(replayed.is_discarded());
  EXPECT_EQ(replayed["interrupted"], true);
  EXPECT_GT(replayed["recorded_ticks"].get<int64_t>(), 1000);
}

TEST(CliRun, WithoutADurationScriptedDevicesRunUntilTheScriptsOrTheTaskEnd) {
  // The introductory's expert takes 15.9 s, longer than the default --duration of 10 s: without
  // one, a session of scripted devices runs on to the task's end (or the scripts'), not to 10 s.
  const std::filesystem::path scripts = source_dir() / "scenarios/scripts/introductory";
  const CommandResult r = run_command(
      cli() + " run --scenario " + (source_dir() / "scenarios/introductory.yaml").string() +
      " --left scripted:" + (scripts / "expert_left.csv").string() +
      " --right scripted:" + (scripts / "expert_right.csv").string() + " --fast");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto out = nlohmann::ordered_json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(out.is_discarded()) << r.out;
  EXPECT_EQ(out["task"]["result"], "success") << out["task"].dump();
  EXPECT_GT(out["haptic"]["ticks"].get<int64_t>(), 10'000);
  // With a simulated device (it never runs out) the default stays 10 s.
  const CommandResult sim = run_command(
      cli() + " run --scenario " + (source_dir() / "scenarios/introductory.yaml").string() +
      " --left simulated --right scripted:" + (scripts / "expert_right.csv").string() + " --fast");
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto sim_out = nlohmann::ordered_json::parse(sim.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(sim_out.is_discarded()) << sim.out;
  EXPECT_EQ(sim_out["haptic"]["ticks"].get<int64_t>(), 10'000);
}

TEST(CliReport, ReplaysARecordedSessionToTheSameTaskAndMetrics) {
  TempDir dir;
  const std::filesystem::path scripts = source_dir() / "scenarios/scripts/introductory";
  const std::filesystem::path session = dir.path() / "session";
  const CommandResult run = run_command(
      cli() + " run --scenario " + (source_dir() / "scenarios/introductory.yaml").string() +
      " --left scripted:" + (scripts / "clumsy_tear_left.csv").string() +
      " --right scripted:" + (scripts / "clumsy_tear_right.csv").string() +
      " --fast --duration 60 --dominant-hand left --record " + session.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto live = nlohmann::ordered_json::parse(run.out, nullptr, false);
  ASSERT_FALSE(live.is_discarded());
  const CommandResult report = run_command(cli() + " report --session " + session.string());
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const auto replayed = nlohmann::ordered_json::parse(report.out, nullptr, false);
  ASSERT_FALSE(replayed.is_discarded()) << report.out;
  EXPECT_EQ(replayed["task"], live["task"]);
  EXPECT_EQ(replayed["metrics"], live["metrics"]);
  EXPECT_EQ(replayed["state_hash"], live["state_hash"]);
  EXPECT_EQ(live["metrics"]["path_length_dominant_m"], live["metrics"]["path_length_left_m"]);
  EXPECT_EQ(replayed["series"]["t_s"].size(), replayed["series"]["insertion_depth_m"].size());
  // The saved metrics.json holds the same, with the series.
  std::ifstream saved_file(session / "metrics.json");
  const auto saved = nlohmann::ordered_json::parse(saved_file, nullptr, false);
  ASSERT_FALSE(saved.is_discarded());
  EXPECT_EQ(saved["metrics"], live["metrics"]);
  EXPECT_EQ(saved["series"], replayed["series"]);

  // CSV: a header, then one metric,value row per metric, in the JSON's order; empty for null.
  const auto csv = dir.path() / "metrics.csv";
  const CommandResult as_csv = run_command(cli() + " report --session " + session.string() +
                                           " --format csv --out " + csv.string());
  ASSERT_EQ(as_csv.exit_code, 0) << as_csv.err;
  std::ifstream rows(csv);
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "metric,value");
  for (const auto& [name, value] : live["metrics"].items()) {
    ASSERT_TRUE(std::getline(rows, line)) << name;
    const auto cells = csv_cells(line);
    ASSERT_GE(cells.size(), 1U);
    EXPECT_EQ(cells[0], name);
    if (value.is_null()) {
      EXPECT_EQ(cells.size(), 1U) << line;
    } else {
      ASSERT_EQ(cells.size(), 2U) << line;
      EXPECT_EQ(std::stod(cells[1]), value.get<double>()) << line;
    }
  }

  // PDF: two pages that render (pdftoppm), with the result, the plots' titles and the metrics'
  // names as text (pdftotext), and ink on the plots: the red of the force and its threshold.
  const auto pdf = dir.path() / "report.pdf";
  const CommandResult as_pdf = run_command(cli() + " report --session " + session.string() +
                                           " --format pdf --out " + pdf.string());
  ASSERT_EQ(as_pdf.exit_code, 0) << as_pdf.err;
  const CommandResult text = run_command("pdftotext " + pdf.string() + " -");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  for (const char* expected : {"failure: duct_injury", "Force on the duct [N]",
                               "Insertion depth [mm]", "Tool speed [mm/s]", "Training metrics",
                               "max_force_duct_n", "NOT MET", "injury threshold 2.00 N"}) {
    EXPECT_NE(text.out.find(expected), std::string::npos) << expected << " in\n" << text.out;
  }
  const auto page = dir.path() / "page";
  const CommandResult render =
      run_command("pdftoppm -r 50 " + pdf.string() + " " + page.string());  // PPM (P6)
  ASSERT_EQ(render.exit_code, 0) << render.err;
  for (const char* n : {"-1.ppm", "-2.ppm"}) {
    ASSERT_TRUE(std::filesystem::exists(page.string() + n)) << n;
  }
  std::ifstream ppm(page.string() + "-1.ppm", std::ios::binary);
  std::string magic;
  int width = 0, height = 0, maxval = 0;
  ppm >> magic >> width >> height >> maxval;
  ppm.get();
  ASSERT_EQ(magic, "P6");
  std::vector<unsigned char> rgb(static_cast<size_t>(width * height * 3));
  ppm.read(reinterpret_cast<char*>(rgb.data()), static_cast<std::streamsize>(rgb.size()));
  int red = 0, ink = 0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    if (rgb[i] > 150 && rgb[i + 1] < 90 && rgb[i + 2] < 90) ++red;
    if (rgb[i] < 128 && rgb[i + 1] < 128 && rgb[i + 2] < 128) ++ink;
  }
  EXPECT_GT(red, 200) << "the force's curve and its threshold";
  EXPECT_GT(ink, 2000) << "text and axes";

  // The report never overwrites its session; a run never records over another.
  const CommandResult over = run_command(cli() + " report --session " + session.string() +
                                         " --out " + (session / "session.lrec").string());
  EXPECT_EQ(over.exit_code, 2);
  EXPECT_NE(over.err.find("would overwrite the session's own session.lrec"), std::string::npos)
      << over.err;
  EXPECT_GT(std::filesystem::file_size(session / "session.lrec"), 1000U);
  const CommandResult again = run_command(
      cli() + " run --scenario " + (source_dir() / "scenarios/introductory.yaml").string() +
      " --left simulated --right simulated --fast --duration 0.1 --record " + session.string());
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_NE(again.err.find("already holds a recorded session"), std::string::npos) << again.err;
  EXPECT_EQ(std::filesystem::status(session).permissions() & std::filesystem::perms::others_all,
            std::filesystem::perms::none);

  // Problems: a folder without a session's record (exit 2, naming the file), a bad format (64).
  const CommandResult missing = run_command(cli() + " report --session " + dir.path().string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("session.json"), std::string::npos) << missing.err;
  const CommandResult bad =
      run_command(cli() + " report --session " + session.string() + " --format html");
  EXPECT_EQ(bad.exit_code, 64);
  EXPECT_NE(bad.err.find("--format expects json, csv or pdf"), std::string::npos) << bad.err;
  const CommandResult no_out =
      run_command(cli() + " report --session " + session.string() + " --format pdf");
  EXPECT_EQ(no_out.exit_code, 64);
  EXPECT_NE(no_out.err.find("--format pdf needs --out FILE"), std::string::npos) << no_out.err;
}

// The §5.5 experiment with a participant typing the shapes (sim/authoring/perception_run.h): the
// same seed gives the same sequence as the engine's; each typed answer is recorded against its
// trial, a line naming no shape is asked again and not counted; the table counts them.
TEST(CliPerception, TypedAnswersAreRecordedPerTrialAndTabulated) {
  const TempDir dir;
  sim::PerceptionSettings ps;
  ps.seed = 7;
  ps.repetitions = 1;
  const Result<sim::PerceptionExperiment> e = sim::PerceptionExperiment::create(ps);
  ASSERT_TRUE(e.ok()) << e.message();
  const std::vector<sim::PerceptionTrial>& trials = e.value().trials();
  ASSERT_EQ(trials.size(), 8U);  // 4 shapes x 2 modes
  // Trial 1 named wrongly; the others right, by name or by number (1-4: sphere, cone, cylinder,
  // cube), one in capitals with spaces; before the first, a line that names nothing.
  std::string typed = "banana\n";
  std::vector<sim::PerceivedShape> named;
  for (size_t i = 0; i < trials.size(); ++i) {
    const sim::PerceivedShape right = trials[i].shape;
    const sim::PerceivedShape n =
        i == 0 ? (right == sim::PerceivedShape::kCube ? sim::PerceivedShape::kSphere
                                                      : sim::PerceivedShape::kCube)
               : right;
    named.push_back(n);
    if (i % 3 == 1) {
      typed += std::to_string(static_cast<int>(n) + 1) + "\n";
    } else if (i % 3 == 2) {
      std::string upper(sim::to_string(n));
      for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      typed += "  " + upper + " \n";
    } else {
      typed += std::string(sim::to_string(n)) + "\n";
    }
  }
  const std::filesystem::path answers = dir.write("typed.txt", typed);
  const std::filesystem::path out = dir.path() / "results";
  const CommandResult r = run_command(
      cli() + " perception --left simulated --right simulated --seed 7 " +
      "--repetitions 1 --trial-limit 5 --out " + out.string() + " < " + answers.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("trial 1 of 8: explore with the "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("trial 8 of 8: explore with the "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("'banana' names no shape"), std::string::npos) << r.err;
  // Each trial's prompt names its probe, never its shape.
  for (const std::string& line : lines_of(r.err)) {
    if (line.rfind("trial ", 0) != 0) continue;
    const size_t of = line.find(" of 8: explore with the ");
    ASSERT_NE(of, std::string::npos) << line;
    const std::string rest = line.substr(of + 24);
    EXPECT_TRUE(rest ==
                    "point probe, then type the shape (sphere, cone, cylinder, cube, or 1-4) "
                    "and Enter" ||
                rest ==
                    "ray probe, then type the shape (sphere, cone, cylinder, cube, or 1-4) "
                    "and Enter")
        << line;
  }
  const std::vector<std::string> rows = lines_of(read_file(out / "answers.csv"));
  ASSERT_EQ(rows.size(), 9U);
  for (size_t i = 0; i < trials.size(); ++i) {
    const std::vector<std::string> c = csv_cells(rows[i + 1]);
    ASSERT_EQ(c.size(), 11U) << rows[i + 1];
    EXPECT_EQ(c[0], std::to_string(i + 1));
    EXPECT_EQ(c[1], sim::to_string(trials[i].shape));
    EXPECT_EQ(c[2], sim::to_string(trials[i].mode));
    EXPECT_NEAR(std::stod(c[4]), trials[i].orientation.w(), 1e-6);
    EXPECT_EQ(c[8], sim::to_string(named[i]));
    EXPECT_EQ(c[9], i == 0 ? "0" : "1");
    const double t = std::stod(c[10]);  // the lines were all there at once: about 0
    EXPECT_TRUE(std::isfinite(t) && t >= 0.0 && t < 30.0) << c[10];
  }
  // The table: one trial per shape and mode, all right but the first trial's.
  const std::vector<std::string> table = lines_of(read_file(out / "results.csv"));
  ASSERT_EQ(table.size(), 9U);
  for (size_t k = 1; k < table.size(); ++k) {
    const std::vector<std::string> c = csv_cells(table[k]);
    ASSERT_GE(c.size(), 4U) << table[k];
    const bool first =
        c[0] == sim::to_string(trials[0].shape) && c[1] == sim::to_string(trials[0].mode);
    EXPECT_EQ(c[2], "1") << table[k];
    EXPECT_EQ(c[3], first ? "0" : "1") << table[k];
  }
}

// A participant who takes 1 s over each shape: each trial's time is about that long, from its
// session's start to the answer's line.
TEST(CliPerception, EachTrialIsTimedFromItsStartToTheAnswer) {
  const TempDir dir;
  const std::filesystem::path out = dir.path() / "results";
  const CommandResult r =
      run_command("{ for k in 1 2 3 4; do sleep 1; echo $k; done; } | " + cli() +
                  " perception --left simulated --right simulated --modes point --repetitions 1 " +
                  "--trial-limit 10 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(read_file(out / "answers.csv"));
  ASSERT_EQ(rows.size(), 5U);
  // From the second on (the first one's wait overlaps the program's start): the 1 s wait, less
  // the previous session's stop and the next one's set-up (0.12 s in the ASan build of a CI run,
  // so not a tight bound).
  for (size_t i = 2; i < rows.size(); ++i) {
    const double t = std::stod(csv_cells(rows[i])[10]);
    EXPECT_GE(t, 0.4) << rows[i];
    EXPECT_LT(t, 5.0) << rows[i];
  }
}

// Standard input ends before the last trial: exit 2, and the files hold the trials answered.
TEST(CliPerception, AnswersThatEndEarlyKeepThoseGivenAndSaySo) {
  const TempDir dir;
  const std::filesystem::path answers = dir.write("typed.txt", "sphere\ncone\ncube\n");
  const std::filesystem::path out = dir.path() / "results";
  const CommandResult r =
      run_command(cli() + " perception --left simulated --right simulated " +
                  "--modes ray --trial-limit 5 --out " + out.string() + " < " + answers.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("the answers ended after 3 of 8 trials"), std::string::npos) << r.err;
  EXPECT_EQ(lines_of(read_file(out / "answers.csv")).size(), 4U);
  const CommandResult bad = run_command(cli() + " perception --left simulated --right simulated " +
                                        "--modes line --repetitions 0 --out " + out.string());
  EXPECT_EQ(bad.exit_code, 64) << bad.err;
  EXPECT_NE(bad.err.find("--modes expects point, ray or point,ray (each once), got 'line'"),
            std::string::npos)
      << bad.err;
  EXPECT_NE(bad.err.find("--repetitions expects a whole number from 1 to 1000, got '0'"),
            std::string::npos)
      << bad.err;
}

TEST(CliPlanExpert, WritesTheScriptsAndRefusesWhatItCannotPlan) {
  TempDir dir;
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const CommandResult ok = run_command(cli() + " plan-expert --scenario " + scenario + " --out " +
                                       dir.path().string() + " --mistake drop");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "clumsy_drop_left.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "clumsy_drop_right.csv"));
  // The expert's plan says how near the right hand comes to the organs it must not touch, and
  // warns where it presses into one: the introductory scenario's shaft grazes the gallbladder on
  // the way in (its figures checked against a brute-force search by
  // PatientRun.ThePlannedRightHandsClearancesAreTheLeastDistancesOverItsKeyframes); a clumsy
  // run's plan does not report them.
  const CommandResult expert =
      run_command(cli() + " plan-expert --scenario " + scenario + " --out " + dir.path().string());
  ASSERT_EQ(expert.exit_code, 0) << expert.err;
  EXPECT_NE(expert.out.find("the right tool's shaft comes within "), std::string::npos)
      << expert.out;
  EXPECT_NE(expert.out.find(" mm of the gallbladder (at 8.8 s)"), std::string::npos) << expert.out;
  EXPECT_NE(expert.out.find("the held catheter comes within "), std::string::npos) << expert.out;
  EXPECT_NE(expert.err.find("laptrainer-cli: warning: the right tool's shaft presses "),
            std::string::npos)
      << expert.err;
  EXPECT_NE(expert.err.find(" mm into the gallbladder at 8.8 s (its axis +0."), std::string::npos)
      << expert.err;
  EXPECT_EQ(expert.err.find("the held catheter presses"), std::string::npos) << expert.err;
  EXPECT_EQ(ok.out.find("comes within"), std::string::npos) << ok.out;
  EXPECT_EQ(ok.err.find("warning"), std::string::npos) << ok.err;
  const CommandResult bad = run_command(cli() + " plan-expert --scenario " + scenario + " --out " +
                                        dir.path().string() + " --mistake sneeze");
  EXPECT_EQ(bad.exit_code, 64);
  EXPECT_NE(
      bad.err.find("--mistake: expected drop, overshoot, tear, cbd or time_limit, got 'sneeze'"),
      std::string::npos)
      << bad.err;
  // A scenario without a task has no insertion to plan: exit 2, saying so.
  const auto no_task = introductory_scenario_copy(dir, [](std::string& t) {
    const size_t at = t.find("\ntask:");
    ASSERT_NE(at, std::string::npos);
    t.erase(at + 1);
  });
  const CommandResult none = run_command(cli() + " plan-expert --scenario " + no_task.string() +
                                         " --out " + dir.path().string());
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("catheter-insertion task"), std::string::npos) << none.err;
}

TEST(CliRun, PhantomFindsLibHdOnTheLibraryPath) {
  // The fake libHD.so stands in for OpenHaptics: found through LD_LIBRARY_PATH as the real one
  // would be through the system's library path.
  const std::string dir = std::filesystem::path(LAP_FAKE_HD).parent_path().string();
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const CommandResult r =
      run_command("LD_LIBRARY_PATH=" + dir + " " + cli() + " run --scenario " + scenario +
                  " --left phantom --right simulated --duration 0.3");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json_field(r.out, "left"), "\"ok\"") << r.out;
  // Real time: a busy machine may pause the session for a stall, but every tick ran and
  // its inputs were kept.
  EXPECT_EQ(json_field(r.out, "recorded_ticks"), "300") << r.out;
}

TEST(CliRun, DeviceProblemsAreClearErrors) {
  TempDir dir;
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const auto bad = dir.write("bad.csv", "0,0,0,0,1,0,0,0,0\n0.1,0,0,0,1,0,0\n");
  CommandResult r = run_command(cli() + " run --scenario " + scenario +
                                " --left scripted:" + bad.string() + " --right simulated --fast");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad.string() + ":2: expected 9 or 10 comma-separated fields"),
            std::string::npos)
      << r.err;
  r = run_command(cli() + " run --scenario " + scenario +
                  " --left phantom --right simulated --fast");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("libHD.so"), std::string::npos) << r.err;
  r = run_command(cli() + " run --scenario " + scenario +
                  " --left simulated+gripper --right simulated --fast");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no actuated gripper found (USB 1209:4c54)"), std::string::npos) << r.err;
  EXPECT_EQ(run_command(cli() + " run --scenario " + scenario + " --left magic --right simulated")
                .exit_code,
            64);
  EXPECT_EQ(run_command(cli() + " run --scenario " + scenario +
                        " --left simulated --right simulated --duration -1")
                .exit_code,
            64);
}

// Starts `laptrainer-cli args...` with stdout and stderr into files; the child's pid.
pid_t spawn_cli(const std::vector<std::string>& args, const std::filesystem::path& out,
                const std::filesystem::path& err, const std::filesystem::path& in = {}) {
  std::vector<std::string> argv_text = {cli()};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (!in.empty()) posix_spawn_file_actions_addopen(&actions, 0, in.c_str(), O_RDONLY, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

// Waits until the session recording into `rec` has its first ticks on disk (a chunk is written
// every 40 ms once the loops run): set-up takes 1.4 s in the ASan build on an idle machine, more
// under load, so a fixed wait could signal a session that has not started.
void wait_until_ticking(const std::filesystem::path& rec) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::error_code ec;
  while (std::chrono::steady_clock::now() < until) {
    const auto size = std::filesystem::file_size(rec / "session.lrec", ec);
    if (!ec && size > 4096) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << "the session recording into " << rec << " never started";
}

// Issue 25: SIGTERM ended `run` at once (exit 143 from the default action, nothing written).
// Now SIGINT and SIGTERM stop the session at the next tick, zero the forces, write the metrics
// and the recording so far, and exit 130 / 143 (README.md).
TEST(CliRun, SigtermAndSigintEndARealTimeRunCleanly) {
  for (const int sig : {SIGTERM, SIGINT}) {
    TempDir dir;
    const std::string rec = (dir.path() / "rec").string();
    const pid_t pid = spawn_cli(
        {"run", "--scenario", (source_dir() / "scenarios/introductory.yaml").string(), "--left",
         "simulated", "--right", "simulated", "--duration", "120", "--record", rec},
        dir.path() / "out.json", dir.path() / "err.txt");
    ASSERT_GT(pid, 0);
    wait_until_ticking(rec);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ASSERT_EQ(kill(pid, sig), 0);
    const auto sent = std::chrono::steady_clock::now();
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    const double shutdown_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    const std::string out = read_file(dir.path() / "out.json");
    const std::string err = read_file(dir.path() / "err.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << "\n" << err;
    EXPECT_EQ(WEXITSTATUS(status), sig == SIGINT ? 130 : 143) << err;
    EXPECT_LT(shutdown_s, 10.0);
    EXPECT_NE(err.find(std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM")),
              std::string::npos)
        << err;
    // Complete, valid JSON on stdout, kept beside the recording.
    const auto j = nlohmann::ordered_json::parse(out, nullptr, /*allow_exceptions=*/false);
    ASSERT_FALSE(j.is_discarded()) << out;
    EXPECT_EQ(json_field(out, "mode"), "\"realtime\"");
    expect_task_contract(j.at("task"));
    const std::string ticks = json_field(out, "recorded_ticks");
    ASSERT_FALSE(ticks.empty()) << out;
    EXPECT_GT(std::stoll(ticks), 0) << out;
    EXPECT_LT(std::stoll(ticks), 120'000) << out;  // stopped long before its duration
    // metrics.json: the same, with the series for plots beside it.
    auto saved = nlohmann::ordered_json::parse(read_file(rec + "/metrics.json"), nullptr, false);
    ASSERT_TRUE(saved.contains("series"));
    saved.erase("series");
    EXPECT_EQ(saved, j);
    EXPECT_GT(std::filesystem::file_size(rec + "/left.lapdev"), 0U);
    EXPECT_GT(std::filesystem::file_size(rec + "/right.lapdev"), 0U);
    // The streamed recording closed cleanly (its end written after the forces were zeroed).
    const auto streamed = lap::sim::read_session_recording(rec + "/session.lrec");
    ASSERT_TRUE(streamed.ok()) << streamed.message();
    EXPECT_FALSE(streamed.value().interrupted);
    EXPECT_TRUE(streamed.value().problems.empty());
    EXPECT_EQ(static_cast<int64_t>(streamed.value().ticks.size()), std::stoll(ticks));
    // Replayed from its recording, the real-time session comes to the same state and metrics
    // (issue 24: the recording keeps which snapshot each loop read from the other).
    const CommandResult report = run_command(cli() + " report --session " + rec);
    ASSERT_EQ(report.exit_code, 0) << report.err;
    const auto replayed = nlohmann::ordered_json::parse(report.out, nullptr, false);
    ASSERT_FALSE(replayed.is_discarded()) << report.out;
    EXPECT_EQ(replayed["state_hash"], j["state_hash"]) << report.err;
    EXPECT_EQ(replayed["metrics"], j["metrics"]);
    EXPECT_EQ(replayed["task"], j["task"]);
  }
}

// SIGINT while the participant explores the second trial: the wait for the answer ends, the
// trial's forces are zeroed, exit 130, and the first trial's answer is on disk.
TEST(CliPerception, SigintStopsTheWaitForAnAnswerAndKeepsThoseGiven) {
  const TempDir dir;
  const std::filesystem::path fifo = dir.path() / "answers";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // Opened here first (read-write: no wait for a reader), so that the program's open for reading
  // does not wait for a writer (posix_spawn's child runs before the parent goes on).
  const int answers = open(fifo.c_str(), O_RDWR);
  ASSERT_GE(answers, 0);
  const std::filesystem::path out = dir.path() / "results";
  const pid_t pid = spawn_cli({"perception", "--left", "simulated", "--right", "simulated",
                               "--modes", "point", "--repetitions", "1", "--out", out.string()},
                              dir.path() / "out.txt", dir.path() / "err.txt", fifo);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(write(answers, "cube\n", 5), 5);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (lines_of(read_file(out / "answers.csv")).size() < 2 &&
         std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the second trial runs
  ASSERT_EQ(kill(pid, SIGINT), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  close(answers);
  const std::string err = read_file(dir.path() / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << "\n" << err;
  EXPECT_EQ(WEXITSTATUS(status), 130) << err;
  EXPECT_NE(err.find("stopped by SIGINT (forces zeroed)"), std::string::npos) << err;
  EXPECT_NE(err.find("trial 2 of 4"), std::string::npos) << err;
  const std::vector<std::string> rows = lines_of(read_file(out / "answers.csv"));
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(csv_cells(rows[1])[8], "cube");
}

// kill -9 in the middle of a recorded real-time session: the recording keeps everything up to
// at most 100 ms before the kill, `report` reads it, says the session was interrupted, and
// replays it.
TEST(CliRun, KilledMidSessionTheRecordingLosesAtMost100Ms) {
  TempDir dir;
  const std::filesystem::path scripts = source_dir() / "scenarios/scripts/introductory";
  const std::string rec = (dir.path() / "rec").string();
  const pid_t pid = spawn_cli(
      {"run", "--scenario", (source_dir() / "scenarios/introductory.yaml").string(), "--left",
       "scripted:" + (scripts / "expert_left.csv").string(), "--right",
       "scripted:" + (scripts / "expert_right.csv").string(), "--duration", "60", "--record", rec},
      dir.path() / "out.json", dir.path() / "err.txt");
  ASSERT_GT(pid, 0);
  wait_until_ticking(rec);
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  const int64_t killed_ns = static_cast<int64_t>(now.tv_sec) * 1000000000 + now.tv_nsec;
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status));
  const auto streamed = lap::sim::read_session_recording(rec + "/session.lrec");
  ASSERT_TRUE(streamed.ok()) << streamed.message();
  const lap::sim::RecordedSession& r = streamed.value();
  EXPECT_TRUE(r.interrupted);
  ASSERT_GT(r.ticks.size(), 500U) << read_file(dir.path() / "err.txt");
  const double lost_s = static_cast<double>(killed_ns - r.ticks.back().wall_ns) * 1e-9;
  EXPECT_LE(lost_s, 0.100) << r.ticks.size() << " ticks recorded";
  EXPECT_GE(lost_s, 0.0);
  // Its frames for seeking reach as far (one every 0.1 s, flushed with the ticks).
  auto frames = lap::sim::RecordedFrames::open(rec + "/session.lrec");
  ASSERT_TRUE(frames.ok()) << frames.message();
  EXPECT_GE(frames.value().duration_s(), static_cast<double>(r.ticks.back().tick) * 1e-3 - 0.3);
  lap::sim::ReplayFrame last;
  ASSERT_TRUE(frames.value().seek(1e9, &last).ok());
  EXPECT_TRUE(last.tools[1].hinge_W.allFinite());

  const CommandResult report = run_command(cli() + " report --session " + rec);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(report.err.find("the session was interrupted"), std::string::npos) << report.err;
  const auto j = nlohmann::ordered_json::parse(report.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << report.out;
  EXPECT_EQ(j["interrupted"], true);
  EXPECT_EQ(j["recording"]["ticks"], static_cast<int64_t>(r.ticks.size()));
  EXPECT_GE(j["haptic"]["ticks"].get<int64_t>(), static_cast<int64_t>(r.ticks.size()));
  if (r.ticks.size() > 2900) {  // the expert takes the catheter at 2.825 s
    EXPECT_EQ(j["task"]["events"][0]["kind"], "catheter_grasped") << j["task"].dump();
  }
}

// The window's binary, which the asan preset does not build (LAP_BUILD_WINDOW=OFF).
class AppHeadless : public ::testing::Test {
 protected:
  void SetUp() override {
#ifndef LAP_HAS_WINDOW
    GTEST_SKIP() << "this build has no window (LAP_BUILD_WINDOW=OFF); the Release build tests it";
#endif
  }
};

TEST_F(AppHeadless, WithoutADisplayItSaysSoAndRunsTheDefaultScenario) {
  const CommandResult r = run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + app());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("no display available"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("organs: 8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("headless run finished"), std::string::npos) << r.out;
}

TEST_F(AppHeadless, ScreenshotWithoutADisplayIsAClearError) {
  const CommandResult r =
      run_command("env -u DISPLAY " + app() + " --screenshot /tmp/x.png --frames 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--screenshot needs a display"), std::string::npos) << r.err;
}

TEST_F(AppHeadless, BadArgumentsAreUsageErrors) {
  EXPECT_EQ(run_command(app() + " --frames zero").exit_code, 64);
  EXPECT_EQ(run_command(app() + " --what").exit_code, 64);
}

TEST_F(AppHeadless, BadScenarioIsReportedNotCrashed) {
  TempDir dir;
  const auto f = dir.write("s.yaml", "version: 3\n");
  const CommandResult r = run_command("env -u DISPLAY " + app() + " --scenario " + f.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(f.string() + ":1: version: expected a whole number from 1 to 1, got '3'"),
            std::string::npos)
      << r.err;
}

// Issue 25, the recording as untrusted input: session.json's "scenario" was followed anywhere
// (with /etc/passwd there, `report` read it and printed it whole in its error). Now it is read
// only from the recording's folder or the shipped scenarios' folders, or where the reviewer says
// (--scenario FILE, --allow-path DIR); and no message quotes more than a short excerpt of a file.
TEST(CliReport, TheScenarioARecordingNamesIsReadOnlyFromTheAllowedFolders) {
  TempDir dir;
  const std::filesystem::path rec = dir.path() / "rec";
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const CommandResult run = run_command(cli() + " run --scenario " + scenario +
                                        " --left simulated --right simulated --fast --duration "
                                        "0.05 --record " +
                                        rec.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string original = read_file(rec / "session.json");
  auto name_scenario = [&](const std::string& path) {
    auto j = nlohmann::ordered_json::parse(original);
    j["scenario"] = path;
    std::ofstream(rec / "session.json", std::ios::trunc) << j.dump(2);
  };
  // A secret beside the recording, and one of the system's.
  const std::string secret = "top-secret-first-line\n" + std::string(5000, 'x') + "\n";
  const std::filesystem::path secret_file = dir.write("secret.yaml", secret);
  for (const std::string& target : {secret_file.string(), std::string("/etc/passwd")}) {
    name_scenario(target);
    const CommandResult r = run_command(cli() + " report --session " + rec.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find((rec / "session.json").string() + ":4: scenario: '" + target +
                         "' is outside the recording's folder and the shipped scenarios' folders"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("give --scenario FILE or --allow-path DIR"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("top-secret"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("root:"), std::string::npos) << r.err;
  }
  // A symbolic link in the recording's folder, named by a relative path: followed, then refused.
  std::filesystem::create_symlink(secret_file, rec / "linked.yaml");
  name_scenario("linked.yaml");
  const CommandResult linked = run_command(cli() + " report --session " + rec.string());
  EXPECT_EQ(linked.exit_code, 2) << linked.err;
  EXPECT_NE(linked.err.find("is outside the recording's folder"), std::string::npos) << linked.err;
  EXPECT_EQ(linked.err.find("top-secret"), std::string::npos) << linked.err;
  // Allowed by the reviewer, the file is read, and its error quotes a short excerpt of it only.
  name_scenario(secret_file.string());
  const CommandResult allowed = run_command(cli() + " report --session " + rec.string() +
                                            " --allow-path " + dir.path().string());
  EXPECT_EQ(allowed.exit_code, 2) << allowed.err;
  EXPECT_NE(allowed.err.find(secret_file.string() +
                             ":1: (document): expected a mapping with version, name and organs, "
                             "got 'top-secret-first-line xxxxxxxxxx"),
            std::string::npos)
      << allowed.err;
  EXPECT_NE(allowed.err.find("...' (5022 bytes)"), std::string::npos) << allowed.err;
  EXPECT_LT(allowed.err.size(), 400U) << allowed.err;
  // --scenario FILE replays with FILE: the recorded path is not followed, and it says so.
  const CommandResult named =
      run_command(cli() + " report --session " + rec.string() + " --scenario " + scenario);
  EXPECT_EQ(named.exit_code, 0) << named.err;
  EXPECT_NE(named.err.find("replayed with " + scenario +
                           " (--scenario) instead of the scenario "
                           "the session names, " +
                           secret_file.string()),
            std::string::npos)
      << named.err;
  // A scenario that came with the recording may not open other folders through its own
  // allowed_paths (no scenario may name an absolute path: `..` up to the root instead).
  const std::filesystem::path carried = rec / "carried.yaml";
  std::string up_to_root;
  for (const auto& part : rec) {
    if (part != rec.root_path() && !part.empty()) up_to_root += "../";
  }
  up_to_root += "..";
  std::ofstream(carried) << "version: 1\nname: carried\nallowed_paths: [" << up_to_root
                         << "]\norgans:\n  - name: liver\n    mesh: " << up_to_root
                         << "/etc/passwd.obj\n";
  name_scenario("carried.yaml");
  const CommandResult carried_run = run_command(cli() + " report --session " + rec.string());
  EXPECT_EQ(carried_run.exit_code, 2) << carried_run.err;
  EXPECT_NE(
      carried_run.err.find(carried.string() + ":3: allowed_paths[0]: directory '" + up_to_root +
                           "' is outside the scenario's folder, and this scenario may not "
                           "open others"),
      std::string::npos)
      << carried_run.err;
}

// Issue 25: a scenario changed on disk while a recorded session ran. session.json was rewritten
// at the end with the digest of the file as it was then, so the replay ran the changed scenario
// without a word. Now session.json is written once, at the start (atomically: no temporary file
// is left), with the digest of the bytes loaded; the run says the file changed, in its warnings
// and metrics.json; and the report notes that the scenario is not the one recorded.
TEST(CliRun, AScenarioChangedWhileARecordedRunRunsIsSaidAndItsRecordKept) {
  TempDir dir;
  const std::filesystem::path scenario = introductory_scenario_copy(dir, [](std::string&) {});
  const std::string loaded = read_file(scenario);
  const std::filesystem::path rec = dir.path() / "rec";
  const pid_t pid =
      spawn_cli({"run", "--scenario", scenario.string(), "--left", "simulated", "--right",
                 "simulated", "--duration", "1.5", "--record", rec.string()},
                dir.path() / "out.json", dir.path() / "err.txt");
  ASSERT_GT(pid, 0);
  // session.json appears once the scenario is loaded and the session is about to start.
  for (int i = 0; i < 2000 && !std::filesystem::exists(rec / "session.json"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const std::string record = read_file(rec / "session.json");
  { std::ofstream(scenario, std::ios::app) << "# edited while the session ran\n"; }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const std::string err = read_file(dir.path() / "err.txt");
  ASSERT_TRUE(WIFEXITED(status)) << err;
  ASSERT_EQ(WEXITSTATUS(status), 0) << err;
  const std::string warning =
      "the scenario " + scenario.string() + " changed on disk while the session ran";
  EXPECT_NE(err.find("laptrainer-cli run: warning: " + warning), std::string::npos) << err;
  // The record is as it was written at the start, with the digest of what was loaded.
  EXPECT_EQ(read_file(rec / "session.json"), record);
  const auto j = nlohmann::json::parse(record);
  char digest[32];
  std::snprintf(digest, sizeof digest, "%016llx",
                static_cast<unsigned long long>(lap::sim::content_digest(loaded)));
  EXPECT_EQ(j["scenario_digest"], digest);
  const auto metrics = nlohmann::json::parse(read_file(rec / "metrics.json"));
  ASSERT_TRUE(metrics["warnings"].is_array());
  EXPECT_TRUE(std::any_of(
      metrics["warnings"].begin(), metrics["warnings"].end(),
      [&](const nlohmann::json& w) { return w.get<std::string>().rfind(warning, 0) == 0; }))
      << metrics["warnings"].dump();
  for (const auto& e : std::filesystem::directory_iterator(rec)) {
    EXPECT_NE(e.path().filename().string().rfind(".session.json", 0), 0U) << e.path();
  }
  const CommandResult report = run_command(cli() + " report --session " + rec.string() +
                                           " --allow-path " + dir.path().string());
  EXPECT_EQ(report.exit_code, 0) << report.err;
  EXPECT_NE(
      report.err.find("note: " + scenario.string() + " has changed since the session was recorded"),
      std::string::npos)
      << report.err;
}

// Issue 25: no size or file-type checks: `validate --scenario /dev/zero` read until memory ran
// out (std::bad_alloc, exit 1), a FIFO blocked for ever. Every file a user names is now a regular
// file within its limit, or a clear error naming it, exit 2. (`timeout` keeps a regression from
// hanging the suite.)
TEST(CliLimits, DevicesFifosAndFoldersAreRefusedUnreadWithExitTwo) {
  TempDir dir;
  const std::string fifo = (dir.path() / "pipe").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string folder = (dir.path() / "folder").string();
  std::filesystem::create_directory(folder);
  const std::string scenario = (source_dir() / "scenarios/introductory.yaml").string();
  const std::string run = cli() + " run --scenario " + scenario + " --right simulated --fast " +
                          "--duration 0.01 --left ";
  struct Case {
    std::string command;
    std::string expected;  // the first line on standard error
  };
  const std::vector<Case> cases = {
      {cli() + " validate --scenario /dev/zero",
       "/dev/zero: is a character device; expected a YAML scenario file, a regular file"},
      {cli() + " validate --scenario " + fifo,
       fifo + ": is a FIFO (named pipe); expected a YAML scenario file, a regular file"},
      {cli() + " validate --scenario " + folder,
       folder + ": is a folder; expected a YAML scenario file, a regular file"},
      {run + "scripted:/dev/zero",
       "laptrainer-cli run: --left: /dev/zero: is a character "
       "device; expected a keyframe script (CSV), a regular file"},
      {run + "scripted:" + fifo, "laptrainer-cli run: --left: " + fifo +
                                     ": is a FIFO (named pipe); expected a keyframe script "
                                     "(CSV), a regular file"},
      {run + "replay:/dev/zero",
       "laptrainer-cli run: --left: /dev/zero: is a character device; "
       "expected a device recording (.lapdev), a regular file"},
      {run + "replay:" + fifo, "laptrainer-cli run: --left: " + fifo +
                                   ": is a FIFO (named pipe); expected a device recording "
                                   "(.lapdev), a regular file"},
      {run + "replay:" + folder, "laptrainer-cli run: --left: " + folder +
                                     ": is a folder; expected a device recording (.lapdev), a "
                                     "regular file"},
      {cli() + " mesh-info --mesh /dev/zero",
       "/dev/zero: is a character device; expected a mesh file, a regular file"},
      {cli() + " mesh-info --mesh " + fifo,
       fifo + ": is a FIFO (named pipe); expected a mesh file, a regular file"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.command);
    const CommandResult r = run_command("timeout 20 " + c.command);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.substr(0, r.err.find('\n')), c.expected);
  }
  // A probe path; an OBJ's material library; a scenario's height map; a glTF's buffer: each a
  // FIFO where a file was expected.
  const std::filesystem::path box = dir.write("box.obj",
                                              "mtllib pipe\nv 0 0 0\nv 1 0 0\n"
                                              "v 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n"
                                              "f 1 4 3\nf 2 3 4\n");
  const CommandResult probe =
      run_command("timeout 20 " + cli() + " probe --mesh " +
                  (source_dir() / "assets/meshes/liver.obj").string() + " --path " + fifo);
  EXPECT_EQ(probe.exit_code, 2) << probe.err;
  EXPECT_NE(probe.err.find(fifo + ": is a FIFO (named pipe); expected a probe path (CSV)"),
            std::string::npos)
      << probe.err;
  const CommandResult mtl =
      run_command("timeout 20 " + cli() + " mesh-info --mesh " + box.string());
  EXPECT_EQ(mtl.exit_code, 2) << mtl.err;
  EXPECT_NE(mtl.err.find(box.string() + ":1: mtllib: 'pipe': " + fifo +
                         ": is a FIFO (named pipe); expected a material library, a regular file"),
            std::string::npos)
      << mtl.err;
  const std::filesystem::path gltf = dir.write("scene.gltf",
                                               R"({"asset": {"version": "2.0"},
"buffers": [{"uri": "pipe", "byteLength": 36}],
"bufferViews": [{"buffer": 0, "byteLength": 36}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
"nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
)");
  const CommandResult buffer =
      run_command("timeout 20 " + cli() + " mesh-info --mesh " + gltf.string());
  EXPECT_EQ(buffer.exit_code, 2) << buffer.err;
  EXPECT_NE(buffer.err.find(gltf.string() + ": not a valid glTF 2.0 file"), std::string::npos)
      << buffer.err;
  const auto textured = introductory_scenario_copy(dir, [&](std::string& t) {
    const std::string at = "material:\n";
    const size_t m = t.find(at);
    ASSERT_NE(m, std::string::npos);
    const size_t indent = m - t.rfind('\n', m) - 1;
    t.insert(m + at.size(), std::string(indent + 2, ' ') +
                                "texture: {kind: image, image: pipe, amplitude_m: 0.0002}\n");
  });
  const CommandResult image =
      run_command("timeout 20 " + cli() + " validate --scenario " + textured.string() +
                  " --allow-path " + dir.path().string());
  EXPECT_EQ(image.exit_code, 2) << image.err;
  EXPECT_NE(image.err.find("texture.image: 'pipe' is a FIFO (named pipe); expected a regular file"),
            std::string::npos)
      << image.err;
  // A recording whose record or stream is a FIFO.
  const std::filesystem::path rec = dir.path() / "rec";
  ASSERT_EQ(run_command(cli() + " run --scenario " + scenario +
                        " --left simulated --right "
                        "simulated --fast --duration 0.05 --record " +
                        rec.string())
                .exit_code,
            0);
  std::filesystem::remove(rec / "session.lrec");
  ASSERT_EQ(mkfifo((rec / "session.lrec").c_str(), 0600), 0);
  const CommandResult lrec =
      run_command("timeout 20 " + cli() + " report --session " + rec.string());
  EXPECT_EQ(lrec.exit_code, 2) << lrec.err;
  EXPECT_NE(lrec.err.find((rec / "session.lrec").string() +
                          ": is a FIFO (named pipe); expected a session's recording"),
            std::string::npos)
      << lrec.err;
  std::filesystem::remove(rec / "session.json");
  ASSERT_EQ(mkfifo((rec / "session.json").c_str(), 0600), 0);
  const CommandResult record =
      run_command("timeout 20 " + cli() + " report --session " + rec.string());
  EXPECT_EQ(record.exit_code, 2) << record.err;
  EXPECT_NE(record.err.find((rec / "session.json").string() +
                            ": is a FIFO (named pipe); expected a session's record"),
            std::string::npos)
      << record.err;
}

}  // namespace
}  // namespace lap::test
