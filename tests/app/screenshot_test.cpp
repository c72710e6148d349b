// Runs the real application under Xvfb (ctest wraps this binary in xvfb-run), asks it for a
// screenshot of the introductory scenario, and checks the picture: not blank; each organ's colour
// where a pinhole projection of the laparoscope's view (sim/runtime/laparoscope.h, at the
// scenario's camera) says the organ is; the instruments' steel tips where their devices put them
// at the start; the heads-up display's texts along the top edge and its gauges at the bottom.

#include <gtest/gtest.h>

#include <QColor>
#include <QImage>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>

#include "hardware/device_recording.h"
#include "sim/runtime/laparoscope.h"
#include "sim/setup/device_factory.h"
#include "sim/setup/scene.h"
#include "tests/test_support.h"

namespace lap::test {
namespace {

struct Pixel {
  double col;
  double row;
};

// VTK's perspective camera at the scope's view: vertical view angle, image aspect ratio, y up
// in the image.
Pixel project(const sim::LaparoscopeView& cam, const Eigen::Vector3d& p, int width, int height) {
  const Eigen::Vector3d forward = cam.view_dir_W;
  const Eigen::Vector3d right = forward.cross(cam.up_W).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  const Eigen::Vector3d d = p - cam.eye_W;
  const double depth = d.dot(forward);
  const double t = std::tan(0.5 * cam.view_angle_deg * M_PI / 180.0);
  const double aspect = static_cast<double>(width) / height;
  const double x_ndc = d.dot(right) / depth / (t * aspect);
  const double y_ndc = d.dot(up) / depth / t;
  return {(x_ndc + 1.0) * 0.5 * width, (1.0 - y_ndc) * 0.5 * height};
}

// The laparoscope's view at the start: the scenario's camera as a scope through its port.
sim::LaparoscopeView scope_view(const sim::Scene& scene) {
  const auto model = sim::LaparoscopeModel::build(scene.scenario.camera);
  EXPECT_TRUE(model.ok()) << model.message();
  return sim::laparoscope_view(model.value(), model.value().home);
}

// Grey (steel, a text's white) rather than tissue: lit (brighter than `floor`) and
// unsaturated.
bool steel_grey(const QColor& c, int floor) {
  const int hi = std::max({c.red(), c.green(), c.blue()});
  const int lo = std::min({c.red(), c.green(), c.blue()});
  return hi > floor && hi - lo < 0.25 * hi;
}

bool white(const QColor& c) { return c.red() > 200 && c.green() > 200 && c.blue() > 200; }

// How many pixels in the rectangle satisfy `is`.
template <class Is>
int count(const QImage& image, int x0, int y0, int x1, int y1, Is is) {
  int n = 0;
  for (int y = std::max(0, y0); y < std::min(image.height(), y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width(), x1); ++x) {
      n += is(image.pixelColor(x, y)) ? 1 : 0;
    }
  }
  return n;
}

// Which organ colour (by chromaticity, so shading does not matter) a pixel is closest to; -1 for
// dark background.
int classify(const QColor& c, const std::vector<Eigen::Vector3d>& organ_colours) {
  const Eigen::Vector3d rgb(c.redF(), c.greenF(), c.blueF());
  if (rgb.sum() < 0.15) return -1;
  const Eigen::Vector3d chroma = rgb / rgb.sum();
  int best = -1;
  double best_d = 0.08;  // must be reasonably close to some organ
  for (size_t i = 0; i < organ_colours.size(); ++i) {
    const double d = (chroma - organ_colours[i] / organ_colours[i].sum()).norm();
    if (d < best_d) {
      best_d = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

// The picture drawn with `quality` (app/render_quality.h): whatever the profile, everything is
// where it belongs, and the heads-up display is there. `instruction_white`: how many white
// pixels the instruction's text at the top left has. `env`: variables set for the run
// ("NAME=value ", or empty); *err: what the program said on stderr (may be null).
void expect_introductory_scene_picture(const std::string& quality, int* instruction_white,
                                       const std::string& env = "", std::string* err = nullptr) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
  TempDir dir;
  const auto png = dir.path() / "shot.png";
  const auto stats_file = dir.path() / "stats.json";
  const auto scenario = source_dir() / "scenarios/introductory.yaml";
  const CommandResult r =
      run_command(env + (bin_dir() / "laptrainer").string() + " --scenario " + scenario.string() +
                  " --screenshot " + png.string() + " --frames 20 --render-quality " + quality +
                  " --stats " + stats_file.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  if (err != nullptr) *err = r.err;
  // What the frames were drawn with: the full profile at the field's own resolution, the fast
  // one at about half of each side (where it starts; then what holds 30 frames/s), never below
  // the floor.
  std::ifstream in(stats_file);
  const nlohmann::json stats = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(stats.is_discarded()) << "the statistics are not JSON";
  EXPECT_EQ(stats["graphics"]["render_quality"], quality);
  EXPECT_FALSE(stats["graphics"]["renderer"].get<std::string>().empty());
  const double scale = stats["graphics"]["scene_scale"].get<double>();
  const bool refused_buffer = env.find("LAPTRAINER_NO_OFFSCREEN_BUFFER") != std::string::npos;
  if (quality == "full" || refused_buffer) {
    EXPECT_EQ(scale, 1.0);
  } else {
    // (20 frames: at most one second's adjustment, 5 % up at most, from the floor.)
    EXPECT_LT(scale, 0.55);
    EXPECT_GE(scale, 0.5 - 1e-9);
  }

  QImage image(QString::fromStdString(png.string()));
  ASSERT_FALSE(image.isNull()) << "the PNG could not be read";
  ASSERT_GT(image.width(), 300);
  ASSERT_GT(image.height(), 200);

  // Not blank: luminance varies and many distinct colours appear.
  double sum = 0.0;
  double sum2 = 0.0;
  std::set<QRgb> colours;
  for (int y = 0; y < image.height(); y += 2) {
    for (int x = 0; x < image.width(); x += 2) {
      const QRgb p = image.pixel(x, y);
      const double l = 0.299 * qRed(p) + 0.587 * qGreen(p) + 0.114 * qBlue(p);
      sum += l;
      sum2 += l * l;
      colours.insert(p);
    }
  }
  const double n = (image.width() / 2.0) * (image.height() / 2.0);
  const double stddev = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  EXPECT_GT(stddev, 10.0);
  EXPECT_GT(colours.size(), 200U);

  const sim::SceneLoadResult scene = sim::load_scene_file(scenario);
  ASSERT_TRUE(scene.ok());
  std::vector<Eigen::Vector3d> organ_colours;
  for (const auto& o : scene.value().organs) organ_colours.push_back(o.color);

  const sim::LaparoscopeView cam = scope_view(scene.value());
  for (size_t i = 0; i < scene.value().organs.size(); ++i) {
    const sim::Organ& organ = scene.value().organs[i];
    // The median of the projected vertices lies inside the organ's silhouette.
    std::vector<double> cols;
    std::vector<double> rows;
    for (const auto& p : organ.mesh.positions) {
      const Pixel px = project(cam, p, image.width(), image.height());
      cols.push_back(px.col);
      rows.push_back(px.row);
    }
    std::nth_element(cols.begin(), cols.begin() + cols.size() / 2, cols.end());
    std::nth_element(rows.begin(), rows.begin() + rows.size() / 2, rows.end());
    const int cx = static_cast<int>(cols[cols.size() / 2]);
    const int cy = static_cast<int>(rows[rows.size() / 2]);
    ASSERT_TRUE(image.valid(cx, cy)) << organ.name << " projects outside the image";
    int hits = 0;
    int total = 0;
    for (int dy = -3; dy <= 3; ++dy) {
      for (int dx = -3; dx <= 3; ++dx) {
        if (!image.valid(cx + dx, cy + dy)) continue;
        ++total;
        hits += classify(image.pixelColor(cx + dx, cy + dy), organ_colours) == static_cast<int>(i)
                    ? 1
                    : 0;
      }
    }
    EXPECT_GE(hits, total * 3 / 4)
        << organ.name << " colour not found at pixel (" << cx << ", " << cy << ")";
  }
  // The corners show the background, not an organ.
  for (const auto& [x, y] : {std::pair{2, 2}, std::pair{image.width() - 3, image.height() - 3}}) {
    EXPECT_EQ(classify(image.pixelColor(x, y), organ_colours), -1) << "corner " << x << "," << y;
  }

  // The instruments: each simulated tool starts with its tip (the jaws' hinge) 10 cm inside its
  // port, pointing at the task's target (sim::default_handle_position), touching nothing; its
  // steel clevis is drawn from the hinge 12 mm up the shaft. Grey steel round its middle.
  for (int side = 0; side < 2; ++side) {
    const sim::ToolSpec* tool = scene.value().scenario.tool(
        side == 0 ? sim::ToolSpec::Side::kLeft : sim::ToolSpec::Side::kRight);
    ASSERT_NE(tool, nullptr);
    const Eigen::Vector3d port = scene.value().scenario.trocar(tool->trocar)->position_m;
    const Eigen::Vector3d axis = (scene.value().task_target_point() - port).normalized();
    const Eigen::Vector3d clevis = port + (0.10 - 0.006) * axis;
    const Pixel px = project(cam, clevis, image.width(), image.height());
    const int x = static_cast<int>(px.col);
    const int y = static_cast<int>(px.row);
    ASSERT_TRUE(image.valid(x, y)) << "tool " << side << " projects outside the image";
    // The fast profile's one light at the camera leaves the steel near the scope at about 65 of
    // 255, where the full picture's spot, brighter near its tip, gives about 110.
    const int floor = quality == "full" ? 70 : 50;
    EXPECT_GE(count(image, x - 4, y - 4, x + 5, y + 5,
                    [floor](const QColor& c) { return steel_grey(c, floor); }),
              8)
        << "no steel at tool " << side << "'s clevis, pixel (" << x << ", " << y << ")";
  }

  // The heads-up display: white text along the top edge (the instruction at the left, the timer
  // at the right) and the gauges' white threshold marks in the bottom corners; the middle of
  // the picture free of it (no white text there: the organs' highlights are small).
  const int w = image.width();
  const int h = image.height();
  *instruction_white = count(image, 0, 0, w / 2, h / 8, white);
  EXPECT_GE(*instruction_white, 100) << "no instruction at the top left";
  EXPECT_GE(count(image, 3 * w / 4, 0, w, h / 8, white), 60) << "no timer at the top right";
  EXPECT_GE(count(image, 0, 7 * h / 8, w / 3, h, white), 40) << "no gauge at the bottom left";
  EXPECT_GE(count(image, 2 * w / 3, 7 * h / 8, w, h, white), 40) << "no gauge at the bottom right";
  EXPECT_LT(count(image, w / 4, h / 3, 3 * w / 4, 2 * h / 3, white), w * h / 400)
      << "white over the middle of the field";
}

TEST(Screenshot, IntroductorySceneShowsEachOrganWhereTheCameraPutsIt) {
  int white_text = 0;
  expect_introductory_scene_picture("full", &white_text);
}

// The fast profile (a station without a GPU) draws the 3D picture smaller and stretches it: the
// organs, the instruments and the display are where they were, and the display's text is as
// sharp as in the full picture (drawn after the stretch, at full size: stretched, its strokes'
// white would spread into grey).
TEST(Screenshot, TheFastPictureShowsTheSameFieldWithASharpDisplay) {
  int full_white = 0;
  int fast_white = 0;
  expect_introductory_scene_picture("full", &full_white);
  expect_introductory_scene_picture("fast", &fast_white);
  EXPECT_GE(fast_white, full_white * 9 / 10) << "the instruction's text is blurred";
  EXPECT_LE(fast_white, full_white * 11 / 10);
}

// A driver that gives no off-screen buffer (ScaledScenePass's fallback, played by
// LAPTRAINER_NO_OFFSCREEN_BUFFER): the fast profile then draws the scene at the window's size,
// everything where it belongs and the display there, and says so once, not on every frame.
TEST(Screenshot, WithoutAnOffScreenBufferTheFastPictureIsDrawnAtTheWindowsSize) {
  int white = 0;
  std::string err;
  expect_introductory_scene_picture("fast", &white, "LAPTRAINER_NO_OFFSCREEN_BUFFER=1 ", &err);
  const std::string said = "gave no off-screen buffer";
  const size_t first = err.find(said);
  EXPECT_NE(first, std::string::npos) << err;
  if (first != std::string::npos) {
    EXPECT_EQ(err.find(said, first + 1), std::string::npos) << "said more than once: " << err;
  }
}

// `--no-hud` (the scenario chooser's previews, app/make-previews.sh): the operative field alone,
// none of the display's white text or marks where the full picture has them (the test above:
// at least 100, 60 and 40 white pixels there), the organs still drawn.
TEST(Screenshot, WithoutTheHeadsUpDisplayTheFieldIsDrawnAlone) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
  TempDir dir;
  const auto png = dir.path() / "shot.png";
  const CommandResult r =
      run_command((bin_dir() / "laptrainer").string() + " --scenario " +
                  (source_dir() / "scenarios/introductory.yaml").string() + " --screenshot " +
                  png.string() + " --frames 20 --render-quality full --no-hud");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  QImage image(QString::fromStdString(png.string()));
  ASSERT_FALSE(image.isNull()) << "the PNG could not be read";
  const int w = image.width();
  const int h = image.height();
  EXPECT_LT(count(image, 0, 0, w / 2, h / 8, white), 10) << "an instruction at the top left";
  EXPECT_LT(count(image, 3 * w / 4, 0, w, h / 8, white), 10) << "a timer at the top right";
  EXPECT_LT(count(image, 0, 7 * h / 8, w / 3, h, white), 10) << "a gauge at the bottom left";
  EXPECT_LT(count(image, 2 * w / 3, 7 * h / 8, w, h, white), 10) << "a gauge at the bottom right";
  // The field is there: most of the middle is lit tissue, not the dark background.
  EXPECT_GT(count(image, w / 4, h / 4, 3 * w / 4, 3 * h / 4,
                  [](const QColor& c) { return c.red() + c.green() + c.blue() > 120; }),
            w * h / 16)
      << "no organs in the middle of the field";
}

// The resident's session is saved when it ends (--record DIR): the inputs of both tools, which
// a replay device reads back, and the metrics an instructor reviews — the loops' statistics and
// no watchdog trip at the start (the schedule begins once the haptic thread is running).
TEST(Screenshot, TheSessionIsSavedForReviewWhenItEnds) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
  TempDir dir;
  const auto rec = dir.path() / "session";
  const CommandResult r =
      run_command((bin_dir() / "laptrainer").string() + " --scenario " +
                  (source_dir() / "scenarios/introductory.yaml").string() + " --screenshot " +
                  (dir.path() / "shot.png").string() + " --frames 20 --record " + rec.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int64_t samples = -1;
  for (const char* side : {"left.lapdev", "right.lapdev"}) {
    const auto recording = hardware::read_device_recording(rec / side);
    ASSERT_TRUE(recording.ok()) << recording.message();
    EXPECT_GT(recording->samples.size(), 10U) << side;
    if (samples >= 0) {
      EXPECT_EQ(static_cast<int64_t>(recording->samples.size()), samples);
    }
    samples = static_cast<int64_t>(recording->samples.size());
  }
  std::ifstream f(rec / "metrics.json");
  ASSERT_TRUE(f.good());
  const auto json = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(json.is_discarded()) << "metrics.json is not JSON";
  EXPECT_EQ(json["mode"], "realtime") << json;
  EXPECT_EQ(json["recorded_ticks"], samples) << json;
  EXPECT_TRUE(json["haptic"].contains("achieved_rate_hz")) << json;
  EXPECT_TRUE(json["haptic"]["late_ticks"].is_number_integer()) << json;
  EXPECT_EQ(json["paused"], false) << json;
  EXPECT_TRUE(json["watchdog_events"].is_array() && json["watchdog_events"].empty()) << json;
}

// `--stats FILE`: at exit, the loops' rates as JSON (the haptic loop's 1 kHz while the window
// draws; the frame rate and start to first frame measured, not asserted here: this machine's
// software renderer and load vary; docs/benchmarks.md has the figures of a dedicated run).
TEST(Screenshot, StatsAtExitGiveTheLoopsRates) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
  TempDir dir;
  const auto stats = dir.path() / "stats.json";
  const CommandResult r = run_command((bin_dir() / "laptrainer").string() + " --scenario " +
                                      (source_dir() / "scenarios/introductory.yaml").string() +
                                      " --quit-after 2 --stats " + stats.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(stats);
  const auto json = nlohmann::json::parse(f, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(json.is_discarded()) << "stats.json is not JSON";
  EXPECT_GT(json["graphics"]["frames"].get<int64_t>(), 2) << json;
  EXPECT_GT(json["graphics"]["fps_mean"].get<double>(), 0.0) << json;
  EXPECT_GT(json["graphics"]["fps_p5"].get<double>(), 0.0) << json;
  EXPECT_LE(json["graphics"]["fps_p5"].get<double>(),
            json["graphics"]["fps_mean"].get<double>() * 1.5)
      << json;
  EXPECT_GT(json["graphics"]["first_frame_s"].get<double>(), 0.0) << json;
  EXPECT_NEAR(json["haptic"]["rate_hz"].get<double>(), 1000.0, 50.0) << json;
  EXPECT_NEAR(json["model"]["rate_hz"].get<double>(), 200.0, 10.0) << json;
  EXPECT_TRUE(json["haptic"]["lateness_p999_us"].is_number()) << json;
}

// An instructor plays a saved session back in the window (--left/--right replay:FILE): the
// replayed session's inputs are the saved ones, tick for tick, bit for bit.
TEST(Screenshot, ASavedSessionPlaysBackInTheWindow) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run (ctest does)";
  TempDir dir;
  const std::string app = (bin_dir() / "laptrainer").string() + " --scenario " +
                          (source_dir() / "scenarios/introductory.yaml").string();
  const auto scripts = source_dir() / "scenarios/scripts";
  const auto first = dir.path() / "first";
  const auto second = dir.path() / "second";
  CommandResult r =
      run_command(app + " --left scripted:" + (scripts / "introductory/expert_left.csv").string() +
                  " --right scripted:" + (scripts / "introductory/expert_right.csv").string() +
                  " --record " + first.string() + " --quit-after 1.5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_command(app + " --left replay:" + (first / "left.lapdev").string() +
                  " --right replay:" + (first / "right.lapdev").string() + " --record " +
                  second.string() + " --quit-after 1.0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* side : {"left.lapdev", "right.lapdev"}) {
    const auto a = hardware::read_device_recording(first / side);
    ASSERT_TRUE(a.ok()) << a.message();
    const auto b = hardware::read_device_recording(second / side);
    ASSERT_TRUE(b.ok()) << b.message();
    ASSERT_GT(b->samples.size(), 300U) << side;
    ASSERT_LE(b->samples.size(), a->samples.size()) << side;
    for (size_t k = 0; k < b->samples.size(); ++k) {
      const hardware::RecordedSample& x = a->samples[k];
      const hardware::RecordedSample& y = b->samples[k];
      ASSERT_EQ(x.tick, y.tick);
      ASSERT_EQ(x.sample.position_W, y.sample.position_W) << side << " tick " << k;
      ASSERT_EQ(x.sample.orientation_W.coeffs(), y.sample.orientation_W.coeffs()) << k;
      ASSERT_EQ(x.sample.gripper_angle_rad, y.sample.gripper_angle_rad) << k;
      ASSERT_EQ(x.sample.buttons, y.sample.buttons) << k;
    }
  }
}

}  // namespace
}  // namespace lap::test
