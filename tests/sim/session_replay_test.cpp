// Issue 24: a session run in real time replays from its recording to the same state_hash. Live,
// each loop takes the other's newest snapshot, and which one that was depends on the threads'
// timing; the streamed recording keeps, per tick, its lateness, its resume and the model
// snapshot and surfaces it read, and per modelling step the tick it read
// (sim/runtime/session_recorder.h), and the replay runs ticks and steps in an order that gives
// each the very snapshot it had (sim/runtime/lockstep_order.h).

#include "sim/report/session_replay.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <string>
#include <thread>

#include "hardware/replay_device.h"
#include "hardware/scripted_device.h"
#include "sim/report/recording_reader.h"
#include "sim/report/session_report.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

// The expert's first 6 s in real time (it takes the catheter at 2.8 s), recorded as
// `run --record` does, with what a loaded machine does to the loops, injected: a late tick, a
// stall (the watchdog pauses; another thread resumes 150 ms later), and a modelling step held up
// 100 ms while the ticks go on; and the trainee's pause (hold, release) 300 ms after the resume.
TEST(RealTimeReplay, ASessionWithLateTicksAStallAndASlowStepReplaysToItsOwnStateHash) {
  const test::TempDir dir;
  const Scene& scene = introductory_scene();
  RuntimeSettings rs;
  rs.duration_s = 6.0;
  rs.realtime_priority = false;  // a test: not above the other tests running beside it
  auto created = Session::create(scene, scripted_devices(kScripts, "expert"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  ASSERT_TRUE(session.inject_lateness(3200, 0.005));  // over 2 periods: a late tick
  ASSERT_TRUE(session.inject_lateness(3600, 0.030));  // over 20 ms: a stall, paused
  session.inject_model_delay(4200, 0.100);
  const fs::path scenario = test::source_dir() / "scenarios/introductory.yaml";
  const Result<std::string> header = session_record_json(scenario, rs);
  ASSERT_TRUE(header.ok());
  ASSERT_TRUE(session.record_to(dir.path() / "session.lrec", header.value()).ok());
  std::atomic<bool> done{false};
  std::thread resumer([&] {
    const auto wait = [](int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); };
    while (!done.load() && !session.paused()) wait(1);
    wait(150);
    session.resume();
    // Then the trainee's pause (hold): no tick while held, the forces ramped back after.
    wait(300);
    session.hold();
    wait(100);
    session.release();
  });
  const SessionMetrics live = session.run();
  done.store(true);
  resumer.join();
  ASSERT_TRUE(save_session(session, live, scenario.string(), false, dir.path().string()).ok());

  // What thread timing decided, as recorded: the injected stall, a resume, some tick that read
  // a model snapshot older than the newest there was (the slow step's ticks), all there.
  const Result<RecordedSession> rec = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(rec.ok()) << rec.message();
  ASSERT_EQ(rec.value().version, 5);
  ASSERT_TRUE(rec.value().problems.empty());
  const std::vector<TickLog>& ticks = rec.value().ticks;
  ASSERT_GT(ticks.size(), 3600U);
  EXPECT_GE(ticks[3600].lateness_s, 0.030);
  EXPECT_TRUE(ticks[3600].paused);
  bool resumed = false, held = false, catheter = false;
  for (const TickLog& t : ticks) {
    resumed = resumed || t.resumed;
    held = held || t.after_hold;
    catheter = catheter || t.touch[1].catheter_held;
  }
  EXPECT_TRUE(resumed);
  EXPECT_TRUE(held);
  EXPECT_TRUE(catheter);  // taken at 2.8 s
  EXPECT_FALSE(live.events.empty());
  ASSERT_FALSE(rec.value().steps.empty());
  // The ticks during the slow step all read the step before it.
  int64_t longest_wait = 0, run = 0;
  for (size_t t = 1; t < ticks.size(); ++t) {
    run = ticks[t].model_steps_read == ticks[t - 1].model_steps_read ? run + 1 : 0;
    longest_wait = std::max(longest_wait, run);
  }
  EXPECT_GE(longest_wait, 50);  // 100 live; fewer if this loaded machine also held up ticks

  // No note: among them, every tick's touches replayed as recorded (touch_departure.h).
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r.value().notes.empty()) << r.value().notes.front();
  const SessionMetrics& again = r.value().metrics;
  EXPECT_EQ(live.state_hash, again.state_hash);
  EXPECT_EQ(live.late_ticks, again.late_ticks);
  ASSERT_EQ(live.events.size(), again.events.size());
  for (size_t i = 0; i < live.events.size(); ++i) {
    EXPECT_EQ(live.events[i].tick, again.events[i].tick);
    EXPECT_EQ(live.events[i].reason, again.events[i].reason);
  }
  EXPECT_EQ(event_kinds(live.task), event_kinds(again.task));
  ASSERT_EQ(live.training.size(), again.training.size());
  for (size_t i = 0; i < live.training.size(); ++i) {
    EXPECT_EQ(std::memcmp(&live.training[i].value, &again.training[i].value, sizeof(double)), 0)
        << live.training[i].name << ": " << live.training[i].value << " vs "
        << again.training[i].value;
  }
  EXPECT_EQ(live.series.duct_force_n, again.series.duct_force_n);
  EXPECT_EQ(live.haptic.ticks(), again.haptic.ticks());

  // Without the reads — the same inputs in plain lockstep, as a LAPREC01 recording replays —
  // the state is another: the reads are what makes the replay exact.
  RuntimeSettings plain = rs;
  plain.fast = true;
  plain.duration_s = static_cast<double>(ticks.size() + 2) / plain.haptic_rate_hz;
  Devices d;
  for (size_t side = 0; side < 2; ++side) {
    hardware::DeviceRecording recorded = rec.value().devices[side];
    recorded.period_s = 1.0 / plain.haptic_rate_hz;
    d[side] = std::make_unique<hardware::ReplayDevice>(std::move(recorded), "replay");
  }
  auto lockstep = Session::create(scene, std::move(d), plain);
  ASSERT_TRUE(lockstep.ok()) << lockstep.message();
  EXPECT_NE(lockstep.value()->run().state_hash, live.state_hash);
}

// A recording cut where a tick read a modelling step that did not reach the file (a damaged
// steps chunk, as a bad disk leaves): the replay runs up to that tick and says why it stopped.
TEST(RealTimeReplay, ARecordingWhoseStepsAreMissingReplaysUpToThemAndSaysSo) {
  const test::TempDir dir;
  const Scene& scene = introductory_scene();
  RuntimeSettings rs = fast(1.0);
  auto created = Session::create(scene, scripted_devices(kScripts, "expert"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  const fs::path scenario = test::source_dir() / "scenarios/introductory.yaml";
  const Result<std::string> header = session_record_json(scenario, rs);
  ASSERT_TRUE(header.ok());
  ASSERT_TRUE(created.value()->record_to(dir.path() / "session.lrec", header.value()).ok());
  const SessionMetrics live = created.value()->run();
  ASSERT_TRUE(
      save_session(*created.value(), live, scenario.string(), true, dir.path().string()).ok());
  // The first steps chunk's mark spoiled: its steps are skipped, and every later one is after a
  // gap.
  std::string bytes = file_text(dir.path() / "session.lrec");
  const uint32_t steps_kind = kChunkSteps;
  std::string mark("LRCK");
  mark.append(reinterpret_cast<const char*>(&steps_kind), 4);
  const size_t at = bytes.find(mark);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 30] = static_cast<char>(bytes[at + 30] ^ 0x5A);  // in its first record: CRC fails
  fs::remove(dir.path() / "session.lrec");
  dir.write("session.lrec", bytes);
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_FALSE(r.value().recording_problems.empty());
  ASSERT_FALSE(r.value().notes.empty());
  EXPECT_NE(r.value().notes.back().find("which the recording does not have whole"),
            std::string::npos)
      << r.value().notes.back();
  EXPECT_LT(r.value().metrics.haptic.ticks(), live.haptic.ticks());
}

// A device whose `failing_write`-th write reports a fault, as a PHANToM's servo thread does: the
// watchdog trips on it. The replay's device takes every command, so the recording keeps what
// each write returned.
class WriteFaultDevice final : public hardware::HapticDevice {
 public:
  WriteFaultDevice(hardware::ScriptedTrajectory t, int64_t failing_write)
      : inner_(std::move(t), "left"), failing_(failing_write) {}
  Status start() override { return inner_.start(); }
  void stop() override {}
  hardware::DeviceStatus read(int64_t tick, double dt,
                              hardware::DeviceSample* out) noexcept override {
    return inner_.read(tick, dt, out);
  }
  hardware::DeviceStatus write(const hardware::DeviceCommand& /*c*/) noexcept override {
    return writes_++ == failing_ ? hardware::DeviceStatus::kError : hardware::DeviceStatus::kOk;
  }
  [[nodiscard]] const hardware::DeviceLimits& limits() const override { return inner_.limits(); }
  [[nodiscard]] std::string_view name() const override { return "left"; }
  [[nodiscard]] std::string last_error() const override { return {}; }

 private:
  hardware::ScriptedDevice inner_;
  int64_t failing_ = 0;
  int64_t writes_ = 0;
};

// The session recorded as `run --record` does, into `dir`.
SessionMetrics run_recorded(Session& session, const RuntimeSettings& rs, const fs::path& dir) {
  const fs::path scenario = test::source_dir() / "scenarios/introductory.yaml";
  const Result<std::string> header = session_record_json(scenario, rs);
  EXPECT_TRUE(header.ok());
  EXPECT_TRUE(session.record_to(dir / "session.lrec", header.value()).ok());
  const SessionMetrics m = session.run();
  EXPECT_TRUE(save_session(session, m, scenario.string(), rs.fast, dir.string()).ok());
  return m;
}

TEST(RealTimeReplay, AFaultADeviceReportedOnAWriteIsReplayed) {
  const test::TempDir dir;
  Devices d = scripted_devices(kScripts, "expert");
  auto left = hardware::load_scripted_trajectory(kScripts / "expert_left.csv");
  ASSERT_TRUE(left.ok()) << left.message();
  d[0] = std::make_unique<WriteFaultDevice>(std::move(left).value(), 500);
  const RuntimeSettings rs = fast(1.0);
  auto created = Session::create(introductory_scene(), std::move(d), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  const SessionMetrics live = run_recorded(*created.value(), rs, dir.path());
  ASSERT_EQ(live.events.size(), 1U);
  EXPECT_EQ(live.events[0].tick, 500);
  EXPECT_EQ(live.events[0].reason, WatchdogReason::kDeviceError);
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().metrics.events.size(), 1U);
  EXPECT_EQ(r.value().metrics.events[0].tick, 500);
  EXPECT_EQ(r.value().metrics.events[0].tool, 0);
  EXPECT_EQ(r.value().metrics.state_hash, live.state_hash);
}

// The recording without its tunings chunks (kind 5), as a damaged disk or a LAPREC03 writer
// leaves it; the other chunks as they were.
std::string without_tunings(const std::string& bytes) {
  uint32_t header = 0;
  std::memcpy(&header, bytes.data() + 8, 4);
  const size_t head = 12 + static_cast<size_t>(header) + 4;
  std::string out = bytes.substr(0, head);
  for (size_t at = head; at < bytes.size();) {
    uint32_t kind = 0, payload = 0;
    std::memcpy(&kind, bytes.data() + at + 4, 4);
    std::memcpy(&payload, bytes.data() + at + 8, 4);
    const size_t next = at + kChunkHeadBytes + payload + 4;
    if (kind != kChunkTunings) out += bytes.substr(at, next - at);
    at = next;
  }
  return out;
}

// Record `index` of the recording's chunks of `kind` (each record `record_bytes` long; a chunk's
// head names its first record) changed by `alter`, and its chunk's checksum made good again: a
// file altered by hand after it was written. False when no chunk holds the record.
bool alter_record(std::string* bytes, uint32_t kind, int64_t index, size_t record_bytes,
                  const std::function<void(char* record)>& alter) {
  std::string mark("LRCK");
  mark.append(reinterpret_cast<const char*>(&kind), 4);
  for (size_t at = bytes->find(mark); at != std::string::npos; at = bytes->find(mark, at + 1)) {
    uint32_t payload_bytes = 0, count = 0;
    int64_t first = 0;
    std::memcpy(&payload_bytes, bytes->data() + at + 8, 4);
    std::memcpy(&count, bytes->data() + at + 12, 4);
    std::memcpy(&first, bytes->data() + at + 16, 8);
    if (first > index || first + count <= index) continue;
    alter(bytes->data() + at + kChunkHeadBytes + static_cast<size_t>(index - first) * record_bytes);
    const uint32_t crc = crc32(bytes->data() + at + 4, kChunkHeadBytes - 4 + payload_bytes);
    std::memcpy(bytes->data() + at + kChunkHeadBytes + payload_bytes, &crc, 4);
    return true;
  }
  return false;
}

// Every organ's surface tuned, at tick `tick`, to values that depend on the tick (as a slider
// dragged across them).
void tune_every_organ(Session& session, int64_t tick) {
  for (int32_t o = 0; o < session.model().organ_count(); ++o) {
    SurfaceParameters p = session.surface_parameters(o);
    p.stiffness_n_per_m *= 0.4 + 0.1 * static_cast<double>((tick / 100 + o) % 9);
    p.friction_static = 0.3;
    p.friction_dynamic = 0.2;
    EXPECT_TRUE(session.tune_surface(o, p));
  }
}

// An author tunes every organ live, several times (issue 26's authoring mode): the recording
// keeps each organ's surface after each tick's tunings, and the replay sets them at the same
// ticks, so the tuned session replays to its own state (issue 24) with a note that it was
// tuned, and every tick's touches as recorded. Without the tunings chunk, the replay names the
// first tick whose tuning it lacks, and departs from the session. The clumsy trainee's right
// tool touches an organ from 2.75 s on (the expert's never does): there the tuning is felt.
TEST(RealTimeReplay, ASessionTunedLiveReplaysToItsOwnStateFromTheRecordedTunings) {
  const test::TempDir dir;
  const RuntimeSettings rs = fast(4.0);
  auto created =
      Session::create(introductory_scene(), scripted_devices(kScripts, "clumsy_tear"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  const int32_t organs = session.model().organ_count();
  session.observe_fast(
      [&](int64_t tick, const HapticSnapshot&, const ModelSnapshot&) {
        if (tick == 500 || tick == 2000 || tick == 3000) tune_every_organ(session, tick);
      },
      100);
  const SessionMetrics live = run_recorded(session, rs, dir.path());
  const Result<RecordedSession> rec = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(rec.ok()) << rec.message();
  EXPECT_TRUE(rec.value().problems.empty());
  // Posted after ticks 500, 2000, 3000: taken at the start of the next.
  ASSERT_EQ(rec.value().tunings.size(), static_cast<size_t>(3 * organs));
  EXPECT_EQ(rec.value().tunings.front().tick, 501);
  EXPECT_EQ(rec.value().tunings.back().tick, 3001);
  EXPECT_EQ(rec.value().tunings.back().organ, organs - 1);
  EXPECT_EQ(rec.value().tunings.back().parameters.friction_static, 0.3);
  EXPECT_TRUE(rec.value().ticks[501].tuned);
  EXPECT_FALSE(rec.value().ticks[502].tuned);

  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().notes.size(), 1U) << (r.value().notes.empty() ? "" : r.value().notes.back());
  EXPECT_EQ(r.value().notes[0], "an author tuned organ surfaces live (" +
                                    std::to_string(3 * organs) +
                                    " changes, from tick 501 (0.501 s) on): the replay renders "
                                    "the recorded values from the ticks that took them");
  EXPECT_EQ(r.value().metrics.state_hash, live.state_hash);

  // The tunings mattered: the same session untuned ends in another state.
  auto untuned =
      Session::create(introductory_scene(), scripted_devices(kScripts, "clumsy_tear"), rs);
  ASSERT_TRUE(untuned.ok()) << untuned.message();
  EXPECT_NE(untuned.value()->run().state_hash, live.state_hash);

  const std::string bytes = without_tunings(file_text(dir.path() / "session.lrec"));
  fs::remove(dir.path() / "session.lrec");
  dir.write("session.lrec", bytes);
  const Result<ReplayedSession> lacking = replay_session(dir.path());
  ASSERT_TRUE(lacking.ok()) << lacking.message();
  ASSERT_GE(lacking.value().notes.size(), 1U);
  EXPECT_EQ(lacking.value().notes[0].rfind("an author tuned organ surfaces live from tick 501 "
                                           "(0.501 s) on, and the recording holds none of the "
                                           "values",
                                           0),
            0U)
      << lacking.value().notes[0];
  EXPECT_NE(lacking.value().metrics.state_hash, live.state_hash);
}

// A tuning record that cannot be (a negative stiffness, its chunk's checksum made good, as a
// recording altered by hand): the reader keeps the tunings before it and says why it stopped;
// the replay names the first tick whose tuning it lacks.
TEST(RealTimeReplay, AnImpossibleTuningRecordIsReportedAndTheReplaySaysWhereItDeparts) {
  const test::TempDir dir;
  const RuntimeSettings rs = fast(1.0);
  auto created = Session::create(introductory_scene(), scripted_devices(kScripts, "expert"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  const auto organs = static_cast<size_t>(session.model().organ_count());
  session.observe_fast(
      [&](int64_t tick, const HapticSnapshot&, const ModelSnapshot&) {
        if (tick == 200 || tick == 600) tune_every_organ(session, tick);
      },
      100);
  run_recorded(session, rs, dir.path());
  std::string bytes = file_text(dir.path() / "session.lrec");
  // The second tuning's first record: its stiffness made negative.
  const bool altered = alter_record(&bytes, kChunkTunings, static_cast<int64_t>(organs),
                                    kTuningRecordBytes, [](char* record) {
                                      const double negative = -1.0;
                                      std::memcpy(record + 16, &negative, 8);
                                    });
  ASSERT_TRUE(altered);
  fs::remove(dir.path() / "session.lrec");
  dir.write("session.lrec", bytes);
  const Result<RecordedSession> rec = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(rec.ok()) << rec.message();
  EXPECT_EQ(rec.value().tunings.size(), organs);
  ASSERT_EQ(rec.value().problems.size(), 1U);
  EXPECT_NE(rec.value().problems[0].find(": a parameter that is not finite, or negative; the "
                                         "tunings from there on are not replayed"),
            std::string::npos)
      << rec.value().problems[0];
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_GE(r.value().notes.size(), 2U);
  EXPECT_EQ(r.value().notes[1],
            "the tuning taken at tick 601 (0.601 s) is not in the recording: from there on the "
            "replay may render other surfaces than the session did");
}

// The same in real time, the author's thread posting as a slider does while the loops run: the
// haptic thread takes each post at whichever tick comes next, and forwards a tuned stiffness to
// the modelling loop's catheter contacts, which take it at the step that reads that tick (not
// whenever it arrives): the replay sets the same values at the same ticks and steps. The clumsy
// trainee's right tool presses an organ while its surface keeps changing.
TEST(RealTimeReplay, AnAuthorTuningFromAnotherThreadInRealTimeReplaysToTheSameState) {
  const test::TempDir dir;
  RuntimeSettings rs;
  rs.duration_s = 3.5;
  rs.realtime_priority = false;
  auto created =
      Session::create(introductory_scene(), scripted_devices(kScripts, "clumsy_tear"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  Session& session = *created.value();
  std::atomic<bool> done{false};
  std::thread author([&] {
    for (int64_t i = 0; !done.load(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(7));
      const auto o = static_cast<int32_t>(i % session.model().organ_count());
      // The organ's scenario stiffness, scaled: the author thread's own copy (reading the
      // haptic thread's parameters while it runs would race).
      SurfaceParameters p;
      p.stiffness_n_per_m =
          introductory_scene().organs[static_cast<size_t>(o)].material.stiffness_n_per_m *
          (0.5 + 0.1 * static_cast<double>(i % 7));
      p.texture_scale = 1.0;
      (void)session.tune_surface(o, p);  // a full mailbox: the next post carries on
    }
  });
  const SessionMetrics live = run_recorded(session, rs, dir.path());
  done.store(true);
  author.join();
  const Result<RecordedSession> rec = read_session_recording(dir.path() / "session.lrec");
  ASSERT_TRUE(rec.ok()) << rec.message();
  EXPECT_TRUE(rec.value().problems.empty());
  EXPECT_GT(rec.value().tunings.size(), 200U);  // one every 7 ms for 3.5 s: about 500
  bool touched = false;  // the right tool on an organ, from 2.75 s on: where tunings are felt
  for (const TickLog& t : rec.value().ticks) touched = touched || t.touch[1].organs > 0;
  EXPECT_TRUE(touched);
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r.value().notes.size(), 1U) << (r.value().notes.empty() ? "" : r.value().notes.back());
  EXPECT_EQ(r.value().metrics.state_hash, live.state_hash);
  EXPECT_EQ(r.value().metrics.haptic.ticks(), live.haptic.ticks());
}

// A recording altered after its checksums were written (or a replay by a build that renders
// differently): the replay names the first tick whose touches it did not give.
TEST(RealTimeReplay, AReplayThatDepartsFromTheRecordedTouchesSaysWhere) {
  const test::TempDir dir;
  const RuntimeSettings rs = fast(0.5);
  auto created = Session::create(introductory_scene(), scripted_devices(kScripts, "expert"), rs);
  ASSERT_TRUE(created.ok()) << created.message();
  run_recorded(*created.value(), rs, dir.path());
  const Result<ReplayedSession> same = replay_session(dir.path());
  ASSERT_TRUE(same.ok()) << same.message();
  EXPECT_TRUE(same.value().notes.empty()) << same.value().notes.front();

  // Tick 100's left tool marked as holding the catheter, its chunk's checksum made good again.
  std::string bytes = file_text(dir.path() / "session.lrec");
  const bool altered = alter_record(&bytes, kChunkTicks, 100, kTickRecordBytes, [](char* record) {
    EXPECT_EQ(record[kTickRecordBytesV2], 0);  // the left tool's flags: holds nothing
    record[kTickRecordBytesV2] = 1;
  });
  ASSERT_TRUE(altered);
  fs::remove(dir.path() / "session.lrec");
  dir.write("session.lrec", bytes);
  const Result<ReplayedSession> r = replay_session(dir.path());
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r.value().recording_problems.empty());
  ASSERT_EQ(r.value().notes.size(), 1U);
  EXPECT_EQ(r.value().notes[0].rfind("the replay departs from the session at tick 100 (0.100 s): "
                                     "live, the left tool held the catheter, touched ",
                                     0),
            0U)
      << r.value().notes[0];
  EXPECT_EQ(r.value().metrics.state_hash, same.value().metrics.state_hash);  // a note, no more
}

}  // namespace
}  // namespace lap::sim
