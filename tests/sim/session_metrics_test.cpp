// The training metrics of whole sessions (sim/runtime/training_metrics.h through the session),
// and a recorded session replayed for review (sim/report/session_replay.h): the expert's and the
// clumsy runs of the introductory scenario score what their events say; recomputed from the
// recording, the metrics equal the live ones bit for bit; a session's record read back names
// the field it cannot use.

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "hardware/scripted_device.h"
#include "sim/report/proficiency.h"
#include "sim/report/session_replay.h"
#include "sim/report/session_report.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"
#include "tests/support/small_disk.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

double metric(const SessionMetrics& m, const std::string& name) {
  for (const Metric& x : m.training) {
    if (x.name == name) return x.value;
  }
  ADD_FAILURE() << "no metric " << name;
  return NAN;
}

// The scripts `stem` on the introductory scene, recorded into `dir` as `run --record` does.
SessionMetrics run_and_record(const std::string& stem, const fs::path& dir, int32_t dominant) {
  const Scene& scene = introductory_scene();
  RuntimeSettings rs = fast(60.0);
  rs.dominant_tool = dominant;
  auto created = Session::create(scene, scripted_devices(kScripts, stem), rs);
  EXPECT_TRUE(created.ok()) << created.message();
  // Streamed as it runs (session.lrec), then saved at the end, as `run --record` does.
  const fs::path scenario = test::source_dir() / "scenarios/introductory.yaml";
  const Result<std::string> header = session_record_json(scenario, rs);
  EXPECT_TRUE(header.ok());
  EXPECT_TRUE(created.value()->record_to(dir / "session.lrec", header.value()).ok());
  const SessionMetrics m = created.value()->run();
  const Status saved = save_session(*created.value(), m, scenario.string(), true, dir.string());
  EXPECT_TRUE(saved.ok()) << saved.message();
  return m;
}

// Equal to the last bit, NaN for NaN.
void expect_same_metrics(const std::vector<Metric>& a, const std::vector<Metric>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(std::memcmp(&a[i].value, &b[i].value, sizeof(double)), 0)
        << a[i].name << ": " << a[i].value << " vs " << b[i].value;
  }
}

// The expert: one closure of the right jaws, which takes the catheter and keeps it; no drop,
// no injury, nothing over a threshold; the depth past the target; the right hand (dominant)
// travels farther than the left, which only steadies the duct.
TEST(SessionMetrics, TheExpertScoresWhatItsEventsSay) {
  const test::TempDir dir;
  const SessionMetrics m = run_and_record("expert", dir.path(), 1);
  ASSERT_EQ(m.task.result, TaskResult::kSuccess);
  EXPECT_EQ(metric(m, "completion_time_s"), m.task.end_s);
  EXPECT_EQ(metric(m, "phase_catheter_grasped_s"), m.task.phase_s[0]);
  EXPECT_EQ(metric(m, "grasp_attempts_right"), 1.0);
  EXPECT_EQ(metric(m, "catheter_drops"), 0.0);
  EXPECT_EQ(metric(m, "injury_events"), 0.0);
  EXPECT_EQ(metric(m, "time_over_threshold_s"), 0.0);
  const TaskSpec& spec = *introductory_scene().scenario.task;
  EXPECT_LE(metric(m, "max_force_duct_n"), spec.duct_injury_force_n);
  EXPECT_GT(metric(m, "max_force_duct_n"), 0.0);
  EXPECT_GE(metric(m, "max_insertion_depth_m"), spec.insertion_depth_m);
  EXPECT_GT(metric(m, "path_length_right_m"), metric(m, "path_length_left_m"));
  EXPECT_EQ(metric(m, "path_length_dominant_m"), metric(m, "path_length_right_m"));
  EXPECT_GE(metric(m, "economy_of_motion_right"), 1.0);
  EXPECT_FALSE(m.series.t_s.empty());
  EXPECT_EQ(m.series.dropped, 0);
}

// Let go on the way: one drop; pulling on the grasped duct: an injury, over its threshold.
TEST(SessionMetrics, TheClumsyRunsScoreTheirMistakes) {
  const SessionMetrics drop = run_scripts(introductory_scene(), kScripts, "clumsy_drop");
  EXPECT_EQ(metric(drop, "catheter_drops"), 1.0);
  EXPECT_EQ(drop.task.result, TaskResult::kFailure);
  EXPECT_TRUE(std::isnan(metric(drop, "completion_time_s")));  // ended, not completed
  const SessionMetrics tear = run_scripts(introductory_scene(), kScripts, "clumsy_tear");
  const TaskSpec& spec = *introductory_scene().scenario.task;
  EXPECT_EQ(metric(tear, "injury_events"), 1.0);
  EXPECT_GT(metric(tear, "max_force_duct_n"), spec.duct_injury_force_n);
  EXPECT_GE(metric(tear, "time_over_threshold_duct_s"), spec.duct_injury_time_s);
  EXPECT_GT(metric(tear, "time_over_threshold_s"), 0.0);
}

// Recomputed from the recording (the report's replay), the metrics equal the live ones exactly,
// and so do the task, the series and the state hash; the dominant hand is kept.
TEST(SessionMetrics, ReplayedFromItsRecordingASessionScoresTheSame) {
  const test::TempDir dir;
  const SessionMetrics live = run_and_record("expert", dir.path(), 0);
  EXPECT_EQ(metric(live, "path_length_dominant_m"), metric(live, "path_length_left_m"));
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r.value().notes.empty());
  EXPECT_EQ(r.value().record.settings.dominant_tool, 0);
  const SessionMetrics& again = r.value().metrics;
  expect_same_metrics(live.training, again.training);
  EXPECT_EQ(event_kinds(live.task), event_kinds(again.task));
  EXPECT_EQ(live.task.end_s, again.task.end_s);
  EXPECT_EQ(live.state_hash, again.state_hash);
  EXPECT_EQ(live.series.depth_m, again.series.depth_m);
  EXPECT_EQ(live.series.duct_force_n, again.series.duct_force_n);
  EXPECT_TRUE(r.value().streamed);
  EXPECT_FALSE(r.value().interrupted);

  // A recording with no whole tick (cut after its header): the .lapdev files written at the end
  // are replayed instead, and the report says so.
  const std::string lrec = file_text(dir.path() / "session.lrec");
  dir.write("session.lrec", lrec.substr(0, lrec.find("LRCK") + 10));
  const Result<ReplayedSession> fallback = replay_session(dir.path());
  ASSERT_TRUE(fallback.ok()) << fallback.message();
  EXPECT_FALSE(fallback.value().streamed);
  ASSERT_FALSE(fallback.value().notes.empty());
  EXPECT_NE(fallback.value().notes.back().find("holds no whole tick"), std::string::npos);
  expect_same_metrics(live.training, fallback.value().metrics.training);
  // Neither a whole tick nor the .lapdev files: a clear error naming the recording.
  fs::remove(dir.path() / "left.lapdev");
  const Result<ReplayedSession> none = replay_session(dir.path());
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("session.lrec: no whole tick could be read"), std::string::npos)
      << none.message();
}

// The record's fields, each checked: the message names session.json and the field.
TEST(SessionMetrics, ABadSessionRecordNamesItsField) {
  const test::TempDir dir;
  run_and_record("clumsy_drop", dir.path(), 1);
  const std::string good = file_text(dir.path() / "session.json");
  struct Case {
    std::string from, to, field;
  };
  const Case cases[] = {
      {"\"mode\": \"fast\"", "\"mode\": \"slow\"", "mode"},
      {"\"dominant_hand\": \"right\"", "\"dominant_hand\": 1", "dominant_hand"},
      {"\"duration_s\": 60.0", "\"duration_s\": -1", "duration_s"},
      {"\"haptic_rate_hz\": 1000.0", "\"haptic_rate_hz\": \"fast\"", "haptic_rate_hz"},
      {"\"haptic_rate_hz\": 1000.0", "\"haptic_rate_hz\": 1e12", "haptic_rate_hz"},
      {"\"duration_s\": 60.0", "\"duration_s\": 1e300", "duration_s"},
      {"\"model_rate_hz\": 200.0", "\"model_rate_hz\": 5000", "model_rate_hz"},
      {"\"version\": 1", "\"version\": 7", "version"},
      {"\"format\": \"laptrainer-session\"", "\"format\": \"other\"", "format"},
  };
  for (const Case& c : cases) {
    std::string text = good;
    const size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    text.replace(at, c.from.size(), c.to);
    dir.write("session.json", text);
    const Result<SessionRecord> r = read_session_record(dir.path());
    ASSERT_FALSE(r.ok()) << c.to;
    EXPECT_NE(r.message().find("session.json"), std::string::npos) << r.message();
    EXPECT_EQ(r.diagnostics().front().field, c.field) << r.message();
  }
  dir.write("session.json", "{\"format\": ");
  EXPECT_NE(read_session_record(dir.path()).message().find("expected a JSON object"),
            std::string::npos);
  // Another scenario's digest: the replay runs, and says the scenario has changed.
  std::string other = good;
  const size_t at = other.find("\"scenario_digest\": \"") + std::strlen("\"scenario_digest\": \"");
  other.replace(at, 16, "0123456789abcdef");
  dir.write("session.json", other);
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().notes.size(), 1u);
  EXPECT_NE(r.value().notes[0].find("has changed since the session was recorded"),
            std::string::npos);
}

// session.json is written once (issue 25): whole or not at all (a temporary file synced, then
// renamed), never over a record already there, for its owner only, leaving nothing else behind.
TEST(SessionRecord, IsWrittenOnceWholeAndNeverOverAnother) {
  const test::TempDir dir;
  const fs::path file = dir.path() / "session.json";
  RuntimeSettings rs;
  const std::string text = session_record_json(test::source_dir() / "scenarios/introductory.yaml",
                                               0x0123456789abcdefULL, rs);
  ASSERT_TRUE(write_session_record(dir.path(), text).ok());
  EXPECT_EQ(file_text(file), text);
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  const Status again = write_session_record(dir.path(), "{}");
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.message(),
            file.string() + ": already exists: a session's record is written once");
  EXPECT_EQ(file_text(file), text);
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir.path())) entries += e.exists() ? 1 : 0;
  EXPECT_EQ(entries, 1U);  // no temporary file left
  const Status nowhere = write_session_record(dir.path() / "missing", text);
  ASSERT_FALSE(nowhere.ok());
  EXPECT_NE(nowhere.message().find("missing/session.json: cannot write a session's record: " +
                                   std::string(std::strerror(ENOENT))),
            std::string::npos)
      << nowhere.message();
  // Read back: what was written.
  const Result<SessionRecord> r = read_session_record(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r.value().scenario_digest, 0x0123456789abcdefULL);
  EXPECT_EQ(r.value().scenario, test::source_dir() / "scenarios/introductory.yaml");
  // A full disk (RLIMIT_FSIZE, as the recording's own test has it): an error naming the file,
  // and neither a half-written record nor a temporary file left.
  const test::TempDir full;
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto previous = signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  rlimit small = old;
  small.rlim_cur = 64;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const Status on_full_disk = write_session_record(full.path(), text);
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, previous);
  ASSERT_FALSE(on_full_disk.ok());
  EXPECT_NE(on_full_disk.message().find((full.path() / "session.json").string() +
                                        ": cannot write a session's record: " +
                                        std::strerror(EFBIG) + " (nothing of it was written)"),
            std::string::npos)
      << on_full_disk.message();
  EXPECT_TRUE(fs::is_empty(full.path()));
}

// The same on a disk that really has no space left (the kernel's ENOSPC, not the file size
// limit's EFBIG): a 64 KB tmpfs of the test's own, filled to the last byte first
// (tests/support/small_disk.h; skipped, saying why, where none can be mounted).
TEST(SessionRecord, ADiskWithNoSpaceLeftGetsNoHalfWrittenRecord) {
  const test::TempDir dir;
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  RuntimeSettings rs;
  const std::string text = session_record_json(test::source_dir() / "scenarios/introductory.yaml",
                                               0x0123456789abcdefULL, rs);
  const test::SmallDiskRun run = test::run_on_a_small_disk(disk, 64U * 1024U, [&] {
    test::fill_the_disk(disk / "filler", 64U * 1024U);
    const Status written = write_session_record(disk, text);
    std::ofstream out(dir.path() / "report.txt");
    out << (written.ok() ? "written" : written.message()) << "\n";
    for (const auto& e : fs::directory_iterator(disk)) out << e.path().filename().string() << "\n";
    return 0;
  });
  if (!run.ran) GTEST_SKIP() << "no small disk could be mounted here: " << run.why_not;
  ASSERT_EQ(run.exit_code, 0);
  const std::vector<std::string> report =
      test::lines_of(test::read_file(dir.path() / "report.txt"));
  ASSERT_EQ(report.size(), 2U) << test::read_file(dir.path() / "report.txt");
  EXPECT_EQ(report[0], (disk / "session.json").string() + ": cannot write a session's record: " +
                           std::strerror(ENOSPC) + " (nothing of it was written)");
  EXPECT_EQ(report[1], "filler");  // neither the record nor its temporary file left
}

// Within two SDs of the experts' mean on the side that counts: lower is better for the time
// (limit 16 + 2·1.5 = 19 s), higher for the depth (limit 13 − 2·1 = 11 mm); an undefined value
// and a metric the session does not have are not met.
TEST(Proficiency, AMetricIsMetWithinTwoSDsOnTheSideThatCounts) {
  ProficiencySpec spec;
  spec.source = "test";
  spec.metrics = {{"completion_time_s", 16.0, 1.5, false, 1},
                  {"max_insertion_depth_m", 0.013, 0.001, true, 2},
                  {"mean_force_liver_n", 0.1, 0.1, false, 3},
                  {"max_force_spleen_n", 1.0, 0.1, false, 4}};
  const auto assess = [&](double time_s, double depth_m) {
    return assess_proficiency(spec, {{"completion_time_s", time_s},
                                     {"max_insertion_depth_m", depth_m},
                                     {"mean_force_liver_n", NAN}});
  };
  auto r = assess(18.9, 0.0111);
  ASSERT_EQ(r.size(), 4U);
  EXPECT_TRUE(r[0].met);
  EXPECT_DOUBLE_EQ(r[0].limit, 19.0);
  EXPECT_TRUE(r[1].met);
  EXPECT_DOUBLE_EQ(r[1].limit, 0.011);
  EXPECT_FALSE(r[2].met);  // undefined in the session
  EXPECT_FALSE(r[3].met);  // not in it
  r = assess(19.1, 0.0109);
  EXPECT_FALSE(r[0].met);
  EXPECT_FALSE(r[1].met);
  const nlohmann::ordered_json j =
      proficiency_to_json(spec, {{"completion_time_s", 12.0}, {"max_insertion_depth_m", 0.02}});
  EXPECT_EQ(j["met"], 2);
  EXPECT_EQ(j["of"], 4);
  EXPECT_EQ(j["all_met"], false);
  EXPECT_EQ(j["metrics"]["max_insertion_depth_m"]["better"], "higher");
  EXPECT_TRUE(j["metrics"]["mean_force_liver_n"]["value"].is_null());
}

}  // namespace
}  // namespace lap::sim
