// The attempts kept on disk (app/session_archive.h): an attempt's folder and description, its
// outcome from the session's report, and an attempt a crash cut short found again, interrupted,
// with the time its streamed recording kept.

#include "app/session_archive.h"

#include <gtest/gtest.h>

#include <QCryptographicHash>
#include <QFile>
#include <fstream>

#include "hardware/scripted_device.h"
#include "sim/report/session_replay.h"
#include "sim/report/session_report.h"
#include "sim/runtime/session.h"
#include "sim/setup/device_factory.h"
#include "tests/test_support.h"

namespace lap::test {
namespace {

namespace fs = std::filesystem;

const fs::path& introductory_scenario() {
  static const fs::path p = source_dir() / "scenarios/introductory.yaml";
  return p;
}

TEST(SessionArchive, AnAttemptsFolderIsItsOwnersWithItsDescription) {
  TempDir root;
  const Result<app::SessionRow> r = app::begin_attempt(
      root.path(), "alice", introductory_scenario(), "Default", "left=simulated", "lab 2");
  ASSERT_TRUE(r.ok()) << r.message();
  const app::SessionRow& a = r.value();
  EXPECT_EQ(a.uuid.size(), 36);
  EXPECT_EQ(a.result, "incomplete");
  const fs::path dir = a.recording_dir.toStdString();
  EXPECT_EQ(dir.parent_path(), root.path());
  EXPECT_EQ(fs::status(dir).permissions(), fs::perms::owner_all);
  // The scenario's version is the SHA-256 of its bytes.
  QFile f(QString::fromStdString(introductory_scenario().string()));
  ASSERT_TRUE(f.open(QIODevice::ReadOnly));
  EXPECT_EQ(a.scenario_version,
            QCryptographicHash::hash(f.readAll(), QCryptographicHash::Sha256).toHex());
  const Result<app::SessionRow> back = app::read_attempt_header(dir);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value().uuid, a.uuid);
  EXPECT_EQ(back.value().trainee, "alice");
  EXPECT_EQ(back.value().devices, "left=simulated");
  EXPECT_EQ(back.value().station, "lab 2");
  EXPECT_EQ(back.value().started_utc, a.started_utc);
  EXPECT_EQ(back.value().scenario_version, a.scenario_version);
}

TEST(SessionArchive, TheOutcomeComesFromTheReport) {
  app::SessionRow a;
  const auto report = nlohmann::ordered_json::parse(R"({
    "task": {"result": "failure", "reasons": ["catheter_dropped", "duct_injury"]},
    "metrics": {"completion_time_s": null, "session_time_s": 6.505},
    "series": {"t_s": [0, 0.1]}})");
  app::finish_attempt(report, &a);
  EXPECT_EQ(a.result, "failure");
  EXPECT_EQ(a.reasons, QStringList({"catheter_dropped", "duct_injury"}));
  EXPECT_TRUE(std::isnan(a.completion_time_s));
  EXPECT_DOUBLE_EQ(a.duration_s, 6.505);
  EXPECT_FALSE(a.interrupted);
  EXPECT_FALSE(a.report_json.contains("series"));  // the plots' data stay in the folder
  EXPECT_TRUE(a.report_json.contains("catheter_dropped"));
}

TEST(SessionArchive, ABadDescriptionIsNamedNotTrusted) {
  TempDir root;
  const fs::path dir = root.path() / "0000";
  fs::create_directories(dir);
  std::ofstream(dir / "attempt.json") << R"({"uuid": "1111", "trainee": "x", "scenario": "y",
    "started_utc": "2026-11-26T10:00:00.000Z"})";
  const Result<app::SessionRow> r = app::read_attempt_header(dir);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("attempt.json"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("uuid: expected the folder's name, 0000"), std::string::npos)
      << r.message();
  std::ofstream(dir / "attempt.json") << "not json";
  EXPECT_FALSE(app::read_attempt_header(dir).ok());
}

// A session streamed into its attempt's folder and cut off as a crash would (no end chunk, no
// metrics.json): found again as not filed, interrupted, with the ticks its recording kept.
TEST(SessionArchive, AnAttemptACrashCutShortIsFoundInterrupted) {
  TempDir root;
  const Result<app::SessionRow> begun = app::begin_attempt(
      root.path(), "bob", introductory_scenario(), "Default", "left=scripted", "lab 2");
  ASSERT_TRUE(begun.ok()) << begun.message();
  const fs::path dir = begun.value().recording_dir.toStdString();
  {
    const sim::SceneLoadResult scene = sim::load_scene_file(introductory_scenario());
    ASSERT_TRUE(scene.ok());
    std::array<std::unique_ptr<hardware::HapticDevice>, 2> devices;
    for (int side = 0; side < 2; ++side) {
      const auto spec = hardware::parse_device_spec(
          "scripted:" + (source_dir() / "scenarios/scripts/introductory" /
                         (side == 0 ? "expert_left.csv" : "expert_right.csv"))
                            .string());
      auto d = sim::make_device(spec.value(), scene.value(), side);
      ASSERT_TRUE(d.ok()) << d.message();
      devices[static_cast<size_t>(side)] = std::move(d).value();
    }
    sim::RuntimeSettings rs;
    rs.fast = true;
    rs.duration_s = 2.0;
    auto session = sim::Session::create(scene.value(), std::move(devices), rs);
    ASSERT_TRUE(session.ok()) << session.message();
    const auto header = sim::session_record_json(introductory_scenario(), rs);
    ASSERT_TRUE(header.ok());
    ASSERT_TRUE(session.value()->record_to(dir / "session.lrec", header.value()).ok());
    (void)session.value()->run();
  }
  // The crash: the end of the file (its end chunk) never reached the disk.
  const fs::path lrec = dir / "session.lrec";
  fs::resize_file(lrec, fs::file_size(lrec) - 40);

  // Another attempt, ended and filed, beside it.
  const Result<app::SessionRow> filed = app::begin_attempt(
      root.path(), "bob", introductory_scenario(), "Default", "left=scripted", "lab 2");
  ASSERT_TRUE(filed.ok());
  std::ofstream(fs::path(filed.value().recording_dir.toStdString()) / "session.lrec") << "x";

  const app::UnfiledAttempts found = app::unfiled_attempts(
      root.path(), [&](const app::SessionRow& r) { return r.uuid == filed.value().uuid; });
  EXPECT_TRUE(found.problems.empty()) << found.problems.front();
  ASSERT_EQ(found.records.size(), 1U);
  const app::SessionRow& a = found.records[0];
  EXPECT_EQ(a.uuid, begun.value().uuid);
  EXPECT_EQ(a.trainee, "bob");
  EXPECT_TRUE(a.interrupted);
  EXPECT_EQ(a.result, "incomplete");
  // Every tick before the end was kept: the 2 s it ran, at 1 kHz.
  EXPECT_DOUBLE_EQ(a.duration_s, 2.0);
  EXPECT_TRUE(a.report_json.contains("\"interrupted\":true")) << a.report_json.toStdString();
  EXPECT_TRUE(a.report_json.contains("\"recorded_ticks\":2000")) << a.report_json.toStdString();
}

}  // namespace
}  // namespace lap::test
