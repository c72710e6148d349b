// Seeking in a recording by its frames (sim/runtime/frame_ring.h, sim/report/recorded_frames.h):
// a recorded session keeps, every 0.1 s, what the 3D view drew; a seek reads the one chunk
// holding the frame at or before the time asked for. The frames are checked against what the
// session itself showed its view at the same ticks, damage is reported and skipped, a file cut
// off seeks up to its last whole chunk, older recordings and other files are refused with why;
// the recorded loop allocates nothing on its thread while it keeps frames.

#include "sim/report/recorded_frames.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <map>
#include <optional>

#include "sim/report/recording_reader.h"
#include "sim/report/session_replay.h"
#include "sim/runtime/session.h"
#include "tests/sim/session_test_support.h"
#include "tests/support/counting_allocator.h"

namespace lap::sim {
namespace {

using namespace session_test;  // NOLINT(google-build-using-namespace): the tests' own helpers

constexpr char kHeader[] = R"({"haptic_rate_hz": 1000})";
const fs::path kScripts = test::source_dir() / "scenarios/scripts/introductory";

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

// Each frames chunk's byte offset and first tick, found by walking the file's chunks.
std::vector<std::pair<size_t, int64_t>> frames_chunks(const std::string& b) {
  std::vector<std::pair<size_t, int64_t>> out;
  uint32_t header = 0;
  std::memcpy(&header, b.data() + 8, 4);
  for (size_t at = 12 + header + 4; at + kChunkHeadBytes + 4 <= b.size();) {
    uint32_t kind = 0, bytes = 0;
    int64_t first = 0;
    std::memcpy(&kind, b.data() + at + 4, 4);
    std::memcpy(&bytes, b.data() + at + 8, 4);
    std::memcpy(&first, b.data() + at + 16, 8);
    if (kind == kChunkFrames) out.emplace_back(at, first);
    at += kChunkHeadBytes + bytes + 4;
  }
  return out;
}

// What the session's view was shown at a tick (Session::observe_fast), kept to compare.
struct Shown {
  std::array<haptics::GripperPose, 2> tools{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_a_W{};
  std::array<std::array<Eigen::Vector3d, 3>, 2> proxy_normal_W{};
  int64_t model_steps = 0;
  std::vector<Eigen::Vector3d> catheter;
  std::vector<SurfaceDeformation> organs;
};

// The left tool pressing into an organ and holding there, recorded, --fast: deformed organs.
struct RecordedPress {
  test::TempDir dir;
  fs::path file = dir.path() / "session.lrec";
  std::map<int64_t, Shown> shown;
  SessionMetrics metrics;

  explicit RecordedPress(double duration_s) {
    auto s = session_over(introductory_scene(), fast(duration_s));
    EXPECT_TRUE(s->record_to(file, kHeader).ok());
    s->observe_fast(
        [this](int64_t tick, const HapticSnapshot& h, const ModelSnapshot& m) {
          Shown& v = shown[tick];
          for (size_t i = 0; i < 2; ++i) {
            v.tools[i] = h.tools[i].pose;
            v.proxy_a_W[i] = h.tools[i].proxy_a_W;
            v.proxy_normal_W[i] = h.tools[i].proxy_normal_W;
          }
          v.model_steps = m.steps;
          v.catheter = m.catheter;
          for (const SurfaceDeformation& d : m.organs) v.organs.push_back(compact(d));
        },
        100);
    metrics = s->run();
  }
};

bool same_pose(const haptics::GripperPose& a, const haptics::GripperPose& b) {
  return a.hinge_W == b.hinge_W && a.shaft_dir_W == b.shaft_dir_W && a.open_dir_W == b.open_dir_W &&
         a.opening_rad == b.opening_rad;
}

TEST(RecordedFrames, EachFrameIsWhatTheViewWasShownAtItsTick) {
  const RecordedPress run(3.0);
  Result<RecordedFrames> opened = RecordedFrames::open(run.file);
  ASSERT_TRUE(opened.ok()) << opened.message();
  RecordedFrames& frames = opened.value();
  EXPECT_TRUE(frames.problems().empty()) << frames.problems().front();
  // A frame every 100 ticks from tick 0, to the last tick run (the press ends at 2.5 s).
  const int64_t ran = run.metrics.haptic.ticks();
  ASSERT_GT(ran, 2000);
  const int64_t last = (ran - 1) / 100 * 100;
  EXPECT_EQ(frames.frame_count(), last / 100 + 1);
  EXPECT_DOUBLE_EQ(frames.duration_s(), static_cast<double>(last) * 1e-3);
  EXPECT_EQ(run.shown.rbegin()->first, last);
  size_t deformed = 0;
  ReplayFrame f;
  for (const auto& [tick, v] : run.shown) {
    ASSERT_TRUE(frames.seek(static_cast<double>(tick) * 1e-3, &f).ok());
    ASSERT_EQ(f.tick, tick);
    EXPECT_EQ(f.model_steps, v.model_steps) << tick;
    for (size_t i = 0; i < 2; ++i) {
      EXPECT_TRUE(same_pose(f.tools[i], v.tools[i])) << tick;
      EXPECT_EQ(f.proxy_a_W[i], v.proxy_a_W[i]) << tick;
      EXPECT_EQ(f.proxy_normal_W[i], v.proxy_normal_W[i]) << tick;
    }
    EXPECT_EQ(f.catheter, v.catheter) << tick;
    ASSERT_EQ(f.organs.size(), v.organs.size());
    for (size_t o = 0; o < v.organs.size(); ++o) {
      const SurfaceDeformation& want = v.organs[o];
      const SurfaceDeformation& got = f.organs[o];
      ASSERT_EQ(got.count, want.count) << "organ " << o << " at tick " << tick;
      EXPECT_EQ(got.vertex, want.vertex);
      for (int32_t k = 0; k < want.count; ++k) {
        // Kept as float32 on disk (session_recorder.h).
        EXPECT_EQ(got.position[static_cast<size_t>(k)],
                  want.position[static_cast<size_t>(k)].cast<float>().cast<double>());
      }
      if (want.count > 0) ++deformed;
    }
  }
  EXPECT_GT(deformed, 10U) << "the pressed organ shows its dent in the frames";
  // Between frames: the one before; before the first: the first; after the end: the last.
  ASSERT_TRUE(frames.seek(1.2349, &f).ok());
  EXPECT_EQ(f.tick, 1200);
  ASSERT_TRUE(frames.seek(-5.0, &f).ok());
  EXPECT_EQ(f.tick, 0);
  ASSERT_TRUE(frames.seek(1e9, &f).ok());
  EXPECT_EQ(f.tick, last);
  ASSERT_TRUE(frames.seek(std::nan(""), &f).ok());
  EXPECT_EQ(f.tick, 0);
  // The whole-file reader counts them too, and the end chunk says none were dropped.
  const Result<RecordedSession> whole = read_session_recording(run.file);
  ASSERT_TRUE(whole.ok());
  EXPECT_EQ(whole.value().version, 5);
  EXPECT_EQ(whole.value().frames_read, last / 100 + 1);
  EXPECT_NE(whole.value().end_json.find("\"frames_dropped\":0"), std::string::npos)
      << whole.value().end_json;
}

TEST(RecordedFrames, ADamagedChunkIsReportedAndASeekIntoItTakesTheFrameBefore) {
  const RecordedPress run(3.0);
  std::string b = bytes_of(run.file);
  const auto chunks = frames_chunks(b);
  ASSERT_GE(chunks.size(), 5U);
  const auto [at, first] = chunks[chunks.size() / 2];
  b[at + kChunkHeadBytes + 20] = static_cast<char>(b[at + kChunkHeadBytes + 20] ^ 0x40);
  write_bytes(run.file, b);
  Result<RecordedFrames> opened = RecordedFrames::open(run.file);
  ASSERT_TRUE(opened.ok()) << opened.message();
  ReplayFrame f;
  ASSERT_TRUE(opened.value().seek(static_cast<double>(first) * 1e-3, &f).ok());
  EXPECT_LT(f.tick, first);
  EXPECT_GE(f.tick, first - 100) << "the frame just before the damaged chunk";
  ASSERT_EQ(opened.value().problems().size(), 1U);
  const std::string& p = opened.value().problems().front();
  EXPECT_NE(p.find("at byte " + std::to_string(at)), std::string::npos) << p;
  EXPECT_NE(p.find("checksum"), std::string::npos) << p;
  // The frames after it still read.
  const int64_t last = (run.metrics.haptic.ticks() - 1) / 100 * 100;
  ASSERT_TRUE(opened.value().seek(static_cast<double>(last) * 1e-3, &f).ok());
  EXPECT_EQ(f.tick, last);
}

// A damaged head is not trusted: a first tick pushed far ahead would hide every chunk after it,
// a count of millions would take gigabytes of frames. Both chunks are left out, the rest reads.
TEST(RecordedFrames, ADamagedChunkHeadHidesNoOtherChunk) {
  const RecordedPress run(2.0);
  std::string b = bytes_of(run.file);
  const auto chunks = frames_chunks(b);
  ASSERT_GE(chunks.size(), 4U);
  const int64_t far = int64_t{1} << 40;
  std::memcpy(b.data() + chunks[1].first + 16, &far, 8);
  const uint32_t millions = 50'000'000;
  std::memcpy(b.data() + chunks[2].first + 12, &millions, 4);
  write_bytes(run.file, b);
  Result<RecordedFrames> opened = RecordedFrames::open(run.file);
  ASSERT_TRUE(opened.ok()) << opened.message();
  EXPECT_EQ(opened.value().problems().size(), 2U);
  EXPECT_EQ(opened.value().chunk_count(), chunks.size() - 2);
  const int64_t last = (run.metrics.haptic.ticks() - 1) / 100 * 100;
  EXPECT_DOUBLE_EQ(opened.value().duration_s(), static_cast<double>(last) * 1e-3);
  ReplayFrame f;
  ASSERT_TRUE(opened.value().seek(1e9, &f).ok());
  EXPECT_EQ(f.tick, last);
  const std::vector<ReplayFrame> all = opened.value().all();
  EXPECT_EQ(static_cast<int64_t>(all.size()), opened.value().frame_count());
  // A payload whose count claims more frames than its bytes hold is refused before storage.
  std::vector<ReplayFrame> frames;
  EXPECT_NE(RecordedFrames::decode(std::string(1000, '\0'), millions, 1e-3, &frames)
                .find("a frame takes at least"),
            std::string::npos);
  EXPECT_TRUE(frames.empty());
}

TEST(RecordedFrames, ACutRecordingSeeksUpToItsLastWholeFramesChunk) {
  const RecordedPress run(3.0);
  const std::string b = bytes_of(run.file);
  const auto chunks = frames_chunks(b);
  ASSERT_GE(chunks.size(), 5U);
  // Cut in the middle of a frames chunk: it and everything after are gone.
  const auto [at, first] = chunks[chunks.size() / 2];
  write_bytes(run.file, b.substr(0, at + kChunkHeadBytes + 30));
  Result<RecordedFrames> opened = RecordedFrames::open(run.file);
  ASSERT_TRUE(opened.ok()) << opened.message();
  EXPECT_LT(opened.value().duration_s(), static_cast<double>(first) * 1e-3);
  EXPECT_GE(opened.value().duration_s(), static_cast<double>(first - 100) * 1e-3);
  ASSERT_FALSE(opened.value().problems().empty());
  EXPECT_NE(opened.value().problems().back().find("cut off"), std::string::npos)
      << opened.value().problems().back();
  ReplayFrame f;
  ASSERT_TRUE(opened.value().seek(1e9, &f).ok());
  EXPECT_LT(f.tick, first);
}

TEST(RecordedFrames, AFileWithoutFramesIsRefusedSayingWhy) {
  const test::TempDir dir;
  // A recording from before frames were kept (a fuzz seed, LAPREC04).
  const Result<RecordedFrames> old = RecordedFrames::open(
      test::source_dir() / "tests/fuzz/corpus/session_recording/expert_30ms_v4.lrec");
  ASSERT_FALSE(old.ok());
  EXPECT_NE(old.message().find("LAPREC04"), std::string::npos) << old.message();
  EXPECT_NE(old.message().find("replay it to seek"), std::string::npos) << old.message();
  write_bytes(dir.path() / "notes.txt", "hello, this is not a recording at all");
  const Result<RecordedFrames> text = RecordedFrames::open(dir.path() / "notes.txt");
  ASSERT_FALSE(text.ok());
  EXPECT_NE(text.message().find("notes.txt"), std::string::npos) << text.message();
  EXPECT_NE(text.message().find("not a laptrainer session recording"), std::string::npos);
  // A FIFO does not hang the review; a folder is not a recording.
  ASSERT_EQ(::mkfifo((dir.path() / "fifo").c_str(), 0600), 0);
  EXPECT_FALSE(RecordedFrames::open(dir.path() / "fifo").ok());
  EXPECT_FALSE(RecordedFrames::open(dir.path()).ok());
  EXPECT_FALSE(RecordedFrames::open(dir.path() / "missing.lrec").ok());
}

TEST(RecordedFrames, AFrameChunkWithImpossibleFramesIsSkippedNotTrusted) {
  const RecordedPress run(1.0);
  const std::string b = bytes_of(run.file);
  const auto chunks = frames_chunks(b);
  ASSERT_GE(chunks.size(), 1U);
  // Decoded as they are, then with a catheter count that runs past the chunk, a tick that
  // goes back, and a pose that is not finite: each refused with why.
  const size_t at = chunks.front().first;
  uint32_t bytes = 0, count = 0;
  std::memcpy(&bytes, b.data() + at + 8, 4);
  std::memcpy(&count, b.data() + at + 12, 4);
  const std::string payload = b.substr(at + kChunkHeadBytes, bytes);
  std::vector<ReplayFrame> frames;
  EXPECT_EQ(RecordedFrames::decode(payload, count, 1e-3, &frames), "");
  ASSERT_EQ(frames.size(), count);
  std::string bad = payload;
  const uint32_t huge = 1U << 20;
  std::memcpy(bad.data() + 16 + 2 * 8 * 37, &huge, 4);
  EXPECT_NE(RecordedFrames::decode(bad, count, 1e-3, &frames).find("catheter particles"),
            std::string::npos);
  bad = payload;
  const double inf = std::numeric_limits<double>::infinity();
  std::memcpy(bad.data() + 16, &inf, 8);
  EXPECT_NE(RecordedFrames::decode(bad, count, 1e-3, &frames).find("not finite"),
            std::string::npos);
  EXPECT_NE(RecordedFrames::decode(payload + "x", count, 1e-3, &frames).find("after the last"),
            std::string::npos);
  EXPECT_NE(RecordedFrames::decode(payload.substr(0, payload.size() - 3), count, 1e-3, &frames),
            "");
  const int64_t negative = -1;
  bad = payload;
  std::memcpy(bad.data(), &negative, 8);
  EXPECT_NE(RecordedFrames::decode(bad, count, 1e-3, &frames).find("negative"), std::string::npos);
}

// The expert's scripted session on the introductory scenario, run with `rs` and recorded into `dir`
// as the application saves one (session.json, session.lrec); null, with a failure, if not.
std::unique_ptr<Session> record_expert_session(const fs::path& dir, const RuntimeSettings& rs) {
  auto created = Session::create(introductory_scene(), scripted_devices(kScripts, "expert"), rs);
  EXPECT_TRUE(created.ok()) << created.message();
  if (!created.ok()) return nullptr;
  const fs::path scenario = test::source_dir() / "scenarios/introductory.yaml";
  const Result<std::string> header = session_record_json(scenario, rs);
  if (!header.ok() || !write_session_record(dir, header.value()).ok() ||
      !created.value()->record_to(dir / "session.lrec", header.value()).ok()) {
    ADD_FAILURE() << "the session could not be recorded into " << dir;
    return nullptr;
  }
  (void)created.value()->run();
  return std::move(created).value();
}

// What the review shows at once (ReplayTimeline::from_recorded_frames): the recorded frames over
// the session's scene, no replay. They are what the replay draws at the same ticks — the expert's
// session replayed (ReplayTimeline::replay) keeps its own frames through the same ticks.
TEST(RecordedFrames, TheReviewShowsTheRecordedFramesAsTheReplayDrawsThem) {
  const test::TempDir dir;
  const Scene& scene = introductory_scene();
  const std::unique_ptr<Session> session = record_expert_session(dir.path(), fast(6.0));
  ASSERT_NE(session, nullptr);

  Result<ReplayTimeline> shown = ReplayTimeline::from_recorded_frames(dir.path());
  ASSERT_TRUE(shown.ok()) << shown.message();
  const ReplayTimeline& at_once = shown.value();
  EXPECT_EQ(at_once.size(), 60U);
  EXPECT_DOUBLE_EQ(at_once.duration_s(), 5.9);
  EXPECT_EQ(at_once.session().scenario_name, scene.scenario.name);
  EXPECT_TRUE(at_once.session().recording_problems.empty());
  const ReplayScene& s = at_once.scene();
  ASSERT_EQ(s.organ_surfaces.size(), static_cast<size_t>(session->organ_count()));
  for (int32_t o = 0; o < session->organ_count(); ++o) {
    EXPECT_EQ(s.organ_surfaces[static_cast<size_t>(o)].positions.size(),
              session->organ_surface(o).positions.size());
  }
  EXPECT_EQ(s.catheter_points, session->model().tissue().catheter_model().particle_count());

  Result<ReplayTimeline> replayed = ReplayTimeline::replay(dir.path(), 0.1);
  ASSERT_TRUE(replayed.ok()) << replayed.message();
  const ReplayTimeline& r = replayed.value();
  ASSERT_GE(r.size(), at_once.size());
  int64_t grasped = 0;
  for (size_t i = 0; i < at_once.size(); ++i) {
    const ReplayFrame& a = at_once.frame(i);
    const ReplayFrame& b = r.frame(r.seek(a.t_s));
    ASSERT_EQ(a.tick, b.tick);
    EXPECT_EQ(a.model_steps, b.model_steps);
    EXPECT_TRUE(same_pose(a.tools[1], b.tools[1])) << a.tick;
    EXPECT_EQ(a.proxy_b_W[1], b.proxy_b_W[1]) << a.tick;
    EXPECT_EQ(a.catheter, b.catheter) << a.tick;
    if (a.catheter != r.frame(0).catheter) ++grasped;
  }
  EXPECT_GT(grasped, 10) << "the catheter moves in the frames once the expert takes it";
}

// The review's Cancel while a live session is replayed (ReplayTimeline::replay's progress says
// stop): the replay, which follows the live loops' recorded order, ends there, its frames cover
// that much, and its notes say so. It went on to the end before (the lockstep replay never
// looked at the stop).
TEST(RecordedFrames, ACancelledReplayOfALiveSessionEndsWhereItWasCancelled) {
  const test::TempDir dir;
  // Real time: its replay follows the loops' recorded order (lockstep).
  ASSERT_NE(record_expert_session(dir.path(), device_fault_run(3.0)), nullptr);

  Result<ReplayTimeline> whole = ReplayTimeline::replay(dir.path(), 0.1);
  ASSERT_TRUE(whole.ok()) << whole.message();
  EXPECT_GT(whole.value().duration_s(), 2.8);
  bool asked = false;
  Result<ReplayTimeline> cancelled = ReplayTimeline::replay(dir.path(), 0.1, [&asked](double done) {
    asked = asked || done >= 0.3;
    return !asked;  // Cancel at 30 %
  });
  ASSERT_TRUE(cancelled.ok()) << cancelled.message();
  const ReplayTimeline& c = cancelled.value();
  EXPECT_GE(c.duration_s(), 0.8);
  EXPECT_LT(c.duration_s(), 1.2) << "the replay went on after the Cancel";
  bool noted = false;
  for (const std::string& n : c.session().notes) {
    noted = noted || n.find("the replay was stopped at") != std::string::npos;
  }
  EXPECT_TRUE(noted);
}

// While it keeps frames, the recorded loop allocates nothing on its own thread: counted from
// tick 1000 to tick 1900 (nine frames taken), the recorder's thread left out.
TEST(RecordedFrames, KeepingFramesAllocatesNothingOnTheLoopsThread) {
  const test::TempDir dir;
  auto s = session_over(introductory_scene(), fast(2.0));
  ASSERT_TRUE(s->record_to(dir.path() / "session.lrec", kHeader).ok());
  std::optional<test::AllocationCounter> counter;
  int64_t counted = -1;
  s->observe_fast(
      [&](int64_t tick, const HapticSnapshot&, const ModelSnapshot&) {
        if (tick == 1000) counter.emplace(test::AllocationCounter::Scope::kThisThread);
        if (tick == 1900) {
          counted = counter->count();
          counter.reset();
        }
      },
      100);
  (void)s->run();
  EXPECT_EQ(counted, 0);
  const Result<RecordedFrames> frames = RecordedFrames::open(dir.path() / "session.lrec");
  ASSERT_TRUE(frames.ok()) << frames.message();
  EXPECT_EQ(frames.value().frame_count(), 20);
  // The counter sees this thread's allocations (else 0 would mean nothing).
  test::AllocationCounter probe(test::AllocationCounter::Scope::kThisThread);
  auto kept = std::make_unique<int>(1);
  EXPECT_EQ(probe.count(), 1);
}

}  // namespace
}  // namespace lap::sim
