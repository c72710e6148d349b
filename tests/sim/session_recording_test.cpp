// The streamed recording (sim/runtime/session_recorder.h) and its reader
// (sim/report/recording_reader.h): a session recorded as it runs reads back to the very samples
// it recorded; a damaged chunk is reported by its offset and the rest still reads; a file cut
// anywhere reads up to its last whole chunk as an interrupted session; a disk that fills up (a
// file size limit, and a real full disk where one can be mounted) stops the recording, not the
// session, and what was written stays.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "hardware/scripted_device.h"
#include "sim/report/recording_reader.h"
#include "sim/report/session_replay.h"
#include "sim/runtime/session.h"
#include "sim/setup/metric_names.h"
#include "tests/sim/session_test_support.h"
#include "tests/support/small_disk.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

std::unique_ptr<Session> expert_session() {
  auto created =
      Session::create(introductory_scene(), scripted_devices(kScripts, "expert"), fast(60.0));
  EXPECT_TRUE(created.ok()) << created.message();
  return std::move(created).value();
}

bool same_bits(const hardware::RecordedSample& a, const hardware::RecordedSample& b) {
  const hardware::DeviceSample& x = a.sample;
  const hardware::DeviceSample& y = b.sample;
  return a.tick == b.tick && a.status == b.status && x.time_s == y.time_s &&
         x.position_W == y.position_W && x.orientation_W.coeffs() == y.orientation_W.coeffs() &&
         x.velocity_W == y.velocity_W && x.gripper_angle_rad == y.gripper_angle_rad &&
         x.buttons == y.buttons;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

TEST(SessionRecording, ReadsBackTheSamplesItRecorded) {
  const test::TempDir dir;
  const auto session = expert_session();
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{\"test\": 1}").ok());
  const SessionMetrics m = session->run();
  for (const std::string& w : m.warnings) EXPECT_EQ(w.find("recording"), std::string::npos) << w;
  const Result<RecordedSession> r = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r.value().interrupted);
  EXPECT_TRUE(r.value().problems.empty()) << testing::PrintToString(r.value().problems);
  EXPECT_EQ(r.value().header_json, "{\"test\": 1}");
  ASSERT_EQ(static_cast<int64_t>(r.value().ticks.size()), m.recorded_ticks);
  for (int side = 0; side < 2; ++side) {
    const auto& live = session->recording(side).samples;
    const auto& read = r.value().devices[static_cast<size_t>(side)].samples;
    ASSERT_EQ(live.size(), read.size());
    for (size_t k = 0; k < live.size(); ++k) ASSERT_TRUE(same_bits(live[k], read[k])) << k;
  }
  EXPECT_NE(r.value().end_json.find("\"result\":\"success\""), std::string::npos)
      << r.value().end_json;
  EXPECT_NE(r.value().events_json.find("catheter_grasped"), std::string::npos);
  // What each tool touched and held, as the haptic loop logged it live. The catheter is held
  // from the grasp the task engine saw on: that step's snapshot reaches the haptic loop within
  // one modelling period (5 ticks), and on a tick the jaws had just closed on it.
  ASSERT_EQ(session->tick_log().size(), r.value().ticks.size());
  int64_t first_held = -1;
  for (size_t k = 0; k < r.value().ticks.size(); ++k) {
    const TickLog& t = r.value().ticks[k];
    ASSERT_EQ(t.touch, session->tick_log()[k].touch) << k;
    if (first_held < 0 && t.touch[1].catheter_held) first_held = t.tick;
  }
  const auto grasped = std::find_if(m.task.events.begin(), m.task.events.end(), [](auto& e) {
    return e.kind == TaskEventKind::kCatheterGrasped;
  });
  ASSERT_NE(grasped, m.task.events.end());
  EXPECT_EQ(grasped->tool, 1);
  const double rate_hz = fast(1.0).haptic_rate_hz;
  const auto grasp_tick = static_cast<int64_t>(std::llround(grasped->t_s * rate_hz));
  EXPECT_GE(first_held, grasp_tick - 5);
  EXPECT_LE(first_held, grasp_tick + 5);
  // What was sent: the grasp's and the duct's forces are in it, never more than the device's.
  double largest = 0.0;
  for (const TickLog& t : r.value().ticks) largest = std::max(largest, t.force_W[1].norm());
  EXPECT_GT(largest, 0.0);
  EXPECT_LE(largest, m.max_force_sent_n);
}

// The recorded touches against the training metrics' own figures, computed apart in the other
// loop: on the hardest patient the clumsy trainee pushes on the gallbladder and tears the duct by
// pulling on it in the jaws. Each modelling step sums the contacts of the haptic tick it read (the
// recording's steps name it), so for the gallbladder the largest push over the ticks the steps
// read is the metric's max_force_gallbladder_n (float in the record), and for every other organ
// but the duct at most its metric (which adds the catheter's push on it, no tool contact; the
// duct's adds the pull of the jaws holding it); and a tool holds the duct throughout the tear. (The
// introductory scene's clumsy run touches no other organ since the segment proxy's passive
// response: its right shaft's graze of the gallbladder carried no force.)
TEST(SessionRecording, TheRecordedTouchesAreTheOnesTheMetricsSaw) {
  const test::TempDir dir;
  const SceneLoadResult scene = load_scene_file(test::source_dir() / "scenarios/patient_hard.yaml");
  ASSERT_TRUE(scene.ok()) << scene.message();
  auto created = Session::create(
      scene.value(),
      scripted_devices(test::source_dir() / "scenarios/scripts/patient_hard", "clumsy_tear"),
      fast(60.0));
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  ASSERT_TRUE(session.record_to(dir.path() / "session.lrec", "{}").ok());
  const SessionMetrics m = session.run();
  const Result<RecordedSession> r = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  const std::vector<TickLog>& ticks = r.value().ticks;
  const size_t organs = m.organ_names.size();
  const auto duct = static_cast<size_t>(session.model().tissue().duct_organ());
  ASSERT_LT(duct, organs);
  std::vector<double> metric(organs, -1.0);
  for (size_t o = 0; o < organs; ++o) {
    // The target duct's metrics are named for its role (training_metrics.cpp).
    const std::string name =
        "max_force_" + (o == duct ? std::string("duct") : snake_case(m.organ_names[o])) + "_n";
    const auto it =
        std::find_if(m.training.begin(), m.training.end(), [&](auto& t) { return t.name == name; });
    ASSERT_NE(it, m.training.end()) << name;
    metric[o] = it->value;
  }
  const auto gallbladder = static_cast<size_t>(
      std::find(m.organ_names.begin(), m.organ_names.end(), "gallbladder") - m.organ_names.begin());
  ASSERT_LT(gallbladder, organs);
  ASSERT_GT(metric[gallbladder], 0.1);
  // The tear is told at its end, after its duration.
  const auto tear = std::find_if(m.task.events.begin(), m.task.events.end(), [](auto& e) {
    return e.kind == TaskEventKind::kDuctInjury && !e.squeeze;
  });
  ASSERT_NE(tear, m.task.events.end());
  const double rate_hz = fast(1.0).haptic_rate_hz;
  const auto tear_from = std::llround((tear->t_s - tear->duration_s) * rate_hz);
  const auto tear_to = std::llround(tear->t_s * rate_hz);
  std::vector<float> peak(organs, 0.0F);
  int64_t tear_steps = 0, tear_steps_held = 0;
  for (const StepLog& k : r.value().steps) {
    if (k.haptic_tick_read < 0) continue;
    ASSERT_LT(static_cast<size_t>(k.haptic_tick_read), ticks.size());
    const TickLog& read = ticks[static_cast<size_t>(k.haptic_tick_read)];
    for (const ToolTouch& t : read.touch) {
      for (size_t o = 0; o < t.listed(); ++o) {
        ASSERT_LT(t.organ[o], organs);
        peak[t.organ[o]] = std::max(peak[t.organ[o]], t.force_n[o]);
      }
    }
    if (k.tick >= tear_from && k.tick <= tear_to) {
      ++tear_steps;
      if (read.touch[0].duct_held || read.touch[1].duct_held) ++tear_steps_held;
    }
  }
  EXPECT_EQ(peak[gallbladder], static_cast<float>(metric[gallbladder]));
  for (size_t o = 0; o < organs; ++o) {
    if (o != duct) {
      EXPECT_LE(peak[o], static_cast<float>(metric[o])) << m.organ_names[o];
    }
  }
  EXPECT_GT(tear_steps, 100);  // a second at 200 Hz
  EXPECT_EQ(tear_steps_held, tear_steps);
}

TEST(SessionRecording, ADamagedChunkIsReportedAndTheRestStillReads) {
  const test::TempDir dir;
  const auto session = expert_session();
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{}").ok());
  const SessionMetrics m = session->run();
  std::string b = bytes_of(dir.path() / "session.lrec");
  // A byte in the middle of the first chunk of ticks from the file's middle on. (Not simply the
  // file's middle byte: where the writer thread cut its chunks depends on the machine's load, and
  // a damaged chunk of frames for seeking leaves no ticks missing. Layout: session_recorder.h.)
  auto u32 = [&](size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return static_cast<size_t>(v);
  };
  ASSERT_GT(b.size(), 12U);
  size_t chunk = 12 + u32(8) + 4;  // magic, header's size, header, its CRC
  size_t at = 0;
  while (at == 0 && chunk + 24 <= b.size()) {
    ASSERT_EQ(b.compare(chunk, 4, "LRCK"), 0) << "at byte " << chunk;
    const size_t payload = u32(chunk + 8);
    if (u32(chunk + 4) == 1 && chunk >= b.size() / 2 && payload > 0) at = chunk + 24 + payload / 2;
    chunk += 24 + payload + 4;
  }
  ASSERT_GT(at, 0U) << "no chunk of ticks in the file's second half";
  b[at] = static_cast<char>(b[at] ^ 0x5A);
  write_bytes(dir.path() / "damaged.lrec", b);
  const Result<RecordedSession> r = read_session_recording(dir.path() / "damaged.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().problems.size(), 2U)  // the chunk, the gap
      << testing::PrintToString(r.value().problems);
  EXPECT_NE(r.value().problems[0].find("checksum does not match"), std::string::npos)
      << r.value().problems[0];
  EXPECT_NE(r.value().problems[0].find("damaged.lrec: at byte "), std::string::npos);
  EXPECT_NE(r.value().problems[1].find("are missing; the replay stops before them"),
            std::string::npos)
      << r.value().problems[1];
  EXPECT_FALSE(r.value().interrupted);  // the end chunk after the damage still read
  const auto n = static_cast<int64_t>(r.value().ticks.size());
  EXPECT_GT(n, 0);  // the chunks before the damaged one
  EXPECT_LT(n, m.recorded_ticks);
  EXPECT_GT(r.value().ticks_read, n);  // the ticks after the gap were read, not replayed
  for (int64_t k = 0; k < n; ++k) {
    ASSERT_TRUE(same_bits(session->recording(0).samples[static_cast<size_t>(k)],
                          r.value().devices[0].samples[static_cast<size_t>(k)]));
  }
}

// Untrusted input: a replay runs every recorded step that read a tick it has, so a file may not
// make it run more than a session records (one per tick, and kStepsBeyondTicks more).
TEST(SessionRecording, MoreStepsThanASessionRecordsAreNotReplayed) {
  const test::TempDir dir;
  const auto session = expert_session();
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{}").ok());
  session->run();
  const Result<RecordedSession> before = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(before.ok()) << before.message();
  ASSERT_TRUE(before.value().problems.empty());
  const size_t ticks = before.value().ticks.size();
  const StepLog last = before.value().steps.back();
  // A steps chunk after the last, each step reading the last tick (all of them could run).
  std::string payload;
  const size_t extra = ticks + 100;
  for (size_t i = 0; i < extra; ++i) {
    append_step_record({last.tick + 5 * static_cast<int64_t>(i + 1), last.haptic_tick_read},
                       &payload);
  }
  std::string chunk;
  const auto put = [&](auto v) { chunk.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  put(kChunkMagic);
  put(kChunkSteps);
  put(static_cast<uint32_t>(payload.size()));
  put(static_cast<uint32_t>(extra));
  put(static_cast<int64_t>(before.value().steps.size()));
  chunk += payload;
  put(crc32(chunk.data() + 4, chunk.size() - 4));
  write_bytes(dir.path() / "flood.lrec", bytes_of(dir.path() / "session.lrec") + chunk);
  const Result<RecordedSession> r = read_session_recording(dir.path() / "flood.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r.value().steps.size(), ticks + kStepsBeyondTicks);
  bool said = false;
  for (const std::string& p : r.value().problems) {
    said = said || p.find("more than a session records") != std::string::npos;
  }
  EXPECT_TRUE(said) << r.value().problems.front();
}

// Cut at 40 random places: never a crash, every whole chunk before the cut, interrupted.
TEST(SessionRecording, CutAnywhereItReadsUpToItsLastWholeChunk) {
  const test::TempDir dir;
  const auto session = expert_session();
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{}").ok());
  const SessionMetrics m = session->run();
  const std::string b = bytes_of(dir.path() / "session.lrec");
  std::mt19937 rng(7);
  int64_t previous = -1;
  std::vector<size_t> cuts;
  for (int k = 0; k < 40; ++k) cuts.push_back(20 + rng() % (b.size() - 40));
  std::sort(cuts.begin(), cuts.end());
  for (const size_t cut : cuts) {
    write_bytes(dir.path() / "cut.lrec", b.substr(0, cut));
    const Result<RecordedSession> r = read_session_recording(dir.path() / "cut.lrec");
    ASSERT_TRUE(r.ok()) << cut << ": " << r.message();
    EXPECT_TRUE(r.value().interrupted) << cut;
    const auto n = static_cast<int64_t>(r.value().ticks.size());
    EXPECT_GE(n, previous) << cut;  // a longer file keeps at least as much
    EXPECT_LE(n, m.recorded_ticks);
    previous = n;
    for (const std::string& p : r.value().problems) {
      EXPECT_NE(p.find("cut off"), std::string::npos) << cut << ": " << p;
    }
  }
  // Not a file at all, and an existing recording never overwritten.
  const Result<RecordedSession> folder = read_session_recording(dir.path());
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.message().find("is a folder; expected a session's recording"), std::string::npos)
      << folder.message();
  EXPECT_FALSE(expert_session()->record_to(dir.path() / "session.lrec", "{}").ok());
  write_bytes(dir.path() / "short.lrec", b.substr(0, 10));
  const Result<RecordedSession> none = read_session_recording(dir.path() / "short.lrec");
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("short.lrec"), std::string::npos);
  EXPECT_NE(none.message().find("not a laptrainer session recording"), std::string::npos)
      << none.message();
}

// The file may grow to 2 MB only (RLIMIT_FSIZE, as a full disk would): the recording stops
// there and says so, the session runs to its end, and the ticks written before stay readable.
TEST(SessionRecording, ADiskThatFillsUpStopsTheRecordingNotTheSession) {
  const test::TempDir dir;
  const auto session = expert_session();
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{}").ok());
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto previous = signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
  rlimit small = old;
  small.rlim_cur = 2 * 1024 * 1024;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  const SessionMetrics m = session->run();
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, previous);
  EXPECT_EQ(m.task.result, TaskResult::kSuccess);  // the session went on
  std::string warning;
  for (const std::string& w : m.warnings) {
    if (w.find("the recording") != std::string::npos) warning = w;
  }
  EXPECT_NE(warning.find("stopped after"), std::string::npos) << warning;
  EXPECT_NE(warning.find("what was written before is kept"), std::string::npos) << warning;
  const Result<RecordedSession> r = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r.value().interrupted);        // no end: it could not be written
  EXPECT_GT(r.value().ticks.size(), 1000U);  // several whole chunks (40 ms of --fast each)
  EXPECT_LT(static_cast<int64_t>(r.value().ticks.size()), m.recorded_ticks);
  EXPECT_LE(fs::file_size(dir.path() / "session.lrec"), 2U * 1024U * 1024U);
}

// The same on a disk that really fills up: a 2 MB tmpfs of the test's own (a child process's
// mount namespace, tests/support/small_disk.h), so that the write fails with the kernel's ENOSPC,
// as on a trainee's full disk, not with RLIMIT_FSIZE's EFBIG above. Skipped, saying why, where
// no such disk can be mounted (no root and no unprivileged user namespaces).
TEST(SessionRecording, ADiskWithNoSpaceLeftStopsTheRecordingNotTheSession) {
  const test::TempDir dir;
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  // In the child: the session recorded onto the small disk, then what the parent checks copied
  // out beside it (the result, the recorded ticks, the warnings, the recording itself).
  const test::SmallDiskRun run = test::run_on_a_small_disk(disk, 2U * 1024U * 1024U, [&] {
    const auto session = expert_session();
    if (!session->record_to(disk / "session.lrec", "{}").ok()) return 3;
    const SessionMetrics m = session->run();
    std::ofstream out(dir.path() / "report.txt");
    out << (m.task.result == TaskResult::kSuccess ? "success" : "not success") << "\n"
        << m.recorded_ticks << "\n";
    for (const std::string& w : m.warnings) out << w << "\n";
    std::error_code e;
    fs::copy_file(disk / "session.lrec", dir.path() / "session.lrec", e);
    return e ? 4 : 0;
  });
  if (!run.ran) GTEST_SKIP() << "no small disk could be mounted here: " << run.why_not;
  ASSERT_EQ(run.exit_code, 0) << "3: the recording could not be opened, 4: not copied out";
  const std::vector<std::string> report =
      test::lines_of(test::read_file(dir.path() / "report.txt"));
  ASSERT_GE(report.size(), 2U);
  EXPECT_EQ(report[0], "success");  // the session went on
  std::string warning;
  for (const std::string& w : report) {
    if (w.find("the recording") != std::string::npos) warning = w;
  }
  EXPECT_NE(warning.find((disk / "session.lrec").string() + " stopped after "), std::string::npos)
      << warning;
  EXPECT_NE(warning.find(std::strerror(ENOSPC)), std::string::npos) << warning;
  EXPECT_NE(warning.find("(what was written before is kept)"), std::string::npos) << warning;
  const Result<RecordedSession> r = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r.value().interrupted);        // no end: it could not be written
  EXPECT_GT(r.value().ticks.size(), 1000U);  // several whole chunks (40 ms of --fast each)
  EXPECT_LT(static_cast<int64_t>(r.value().ticks.size()), std::stoll(report[1]));
}

// A session longer than the recording space reserved for it (record_s): the recording keeps
// what fitted and says, when read, that the rest did not.
TEST(SessionRecording, ARecordingShorterThanItsSessionSaysSo) {
  const test::TempDir dir;
  RuntimeSettings rs = fast(2.0);
  rs.record_s = 1.0;
  const auto session = scripted_session(rs);
  ASSERT_TRUE(session->record_to(dir.path() / "session.lrec", "{}").ok());
  const SessionMetrics m = session->run();
  const Result<RecordedSession> r = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_FALSE(r.value().interrupted);
  EXPECT_LT(static_cast<int64_t>(r.value().ticks.size()), m.haptic.ticks());
  ASSERT_EQ(r.value().problems.size(), 1U) << testing::PrintToString(r.value().problems);
  EXPECT_NE(r.value().problems[0].find("(the space reserved for it ran out)"), std::string::npos);
}

TEST(SessionRecording, Crc32IsTheStandardOne) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926U);  // the check value of CRC-32/ISO-HDLC
  EXPECT_EQ(crc32("", 0), 0U);
}

}  // namespace
}  // namespace lap::sim
