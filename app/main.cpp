// laptrainer: the desktop application.
//   laptrainer [--scenario FILE] [--left DEV] [--right DEV] [--record DIR] [--quit-after S]
//              [--screenshot PNG --frames N] [--size WxH] [--stats FILE]
// Without options that name a session the window opens at sign-in (a training session from
// sign-in to result: main_window.h). --scenario, --left, --right, --record or --screenshot name
// a session: the window runs it at once, without signing in (the attempt is not filed), and
// shows its result when its task ends. --quit-after and --stats apply either way.
// With no display it says so, loads and checks the scenario without a window and prints a short
// summary.

#include <vtkAutoInit.h>

#include <QApplication>
#include <QSurfaceFormat>
#include <QTimer>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/main_window.h"
#include "app/pages/page_style.h"
#include "app/render_quality.h"
#include "app/review/review_window.h"
#include "app/run_stats.h"
#include "hardware/device_spec.h"
#include "sim/setup/scenario_loader.h"
#include "sim/setup/scene.h"

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkInteractionStyle);

namespace {

constexpr int kExitProblems = 2;
constexpr int kExitUsage = 64;

const char* const kUsage =
    "usage: laptrainer [--scenario FILE] [--left DEV] [--right DEV] [--record DIR]\n"
    "                  [--quit-after S] [--screenshot PNG --frames N] [--size WxH]\n"
    "                  [--stats FILE] [--render-quality auto|full|fast] [--no-hud]\n"
    "       laptrainer --review [--trainee NAME]\n"
    "  Without options that name a session, the window opens at sign-in. --scenario, --left,\n"
    "  --right, --record and --screenshot name one: it runs at once, without signing in.\n"
    "  --review          open the instructor's review of the station's sessions instead (an\n"
    "                    instructor signs in; --trainee NAME: that trainee's own sessions)\n"
    "  --scenario FILE   scenario to run (default: scenarios/default.yaml)\n"
    "  --left DEV, --right DEV  the tools' devices: simulated (default, keyboard and mouse),\n"
    "                    scripted:FILE, replay:FILE (a saved session), phantom:NAME\n"
    "  --quit-after S    close the window after S seconds (the session saved if --record)\n"
    "  --record DIR      when the session ends, save its inputs (for replay) and metrics\n"
    "                    there: left.lapdev, right.lapdev, metrics.json\n"
    "  --screenshot PNG  render N frames, write the last one to PNG and exit\n"
    "  --frames N        frames to render before the screenshot (default 10)\n"
    "  --size WxH        the operative field's size in pixels (screenshots, benchmarks)\n"
    "  --stats FILE      at exit, write how fast the loops ran as JSON: graphics frame rate\n"
    "                    (mean, 5th percentile), start to first frame, haptic rate and its\n"
    "                    p99.9 lateness, modelling rate\n"
    "  --render-quality Q  how the operative field is drawn, for this run: full (mipmapped\n"
    "                    textures, the scope's spot light and a fill, full resolution), fast\n"
    "                    (for a station without a GPU: no mipmaps, one light at the camera,\n"
    "                    the 3D picture at 0.5 to 1 of the field's size, as large as 30\n"
    "                    frames/s allow), auto (fast on a software renderer; the default,\n"
    "                    or what View > Picture Quality saved)\n"
    "  --no-hud          draw the operative field alone, without the heads-up display (the\n"
    "                    scenario chooser's previews, app/make-previews.sh)\n";

struct Options {
  bool names_session = false;  ///< an option that names a session was given: run it at once
  std::string scenario;
  std::string screenshot;
  std::string record;
  std::string stats;
  std::string trainee;
  bool review = false;
  bool hud = true;  ///< the heads-up display over the field (--no-hud: without)
  std::array<lap::hardware::DeviceSpec, 2> devices{};
  int field_width = 0;  ///< --size: the operative field's size [px]; 0: the window's
  int field_height = 0;
  double quit_after_s = 0.0;
  std::optional<lap::app::RenderQualityChoice> render_quality;
  int frames = 10;
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc) {
        std::cerr << "laptrainer: option " << a << " needs a value\n";
        return false;
      }
      out = argv[++i];
      return true;
    };
    std::string v;
    if (a == "--scenario" || a == "--left" || a == "--right" || a == "--record" ||
        a == "--screenshot") {
      o.names_session = true;
    }
    if (a == "--scenario") {
      if (!value(o.scenario)) return false;
    } else if (a == "--screenshot") {
      if (!value(o.screenshot)) return false;
    } else if (a == "--record") {
      if (!value(o.record)) return false;
    } else if (a == "--review") {
      o.review = true;
    } else if (a == "--trainee") {
      if (!value(o.trainee)) return false;
    } else if (a == "--stats") {
      if (!value(o.stats)) return false;
    } else if (a == "--left" || a == "--right") {
      std::string text;
      if (!value(text)) return false;
      const auto spec = lap::hardware::parse_device_spec(text);
      if (!spec.ok()) {
        std::cerr << "laptrainer: " << a << ": " << spec.message() << "\n";
        return false;
      }
      o.devices[a == "--left" ? 0 : 1] = spec.value();
    } else if (a == "--quit-after") {
      std::string v;
      if (!value(v)) return false;
      char* end = nullptr;
      const double s = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(s > 0.0 && s < 1e6)) {
        std::cerr << "laptrainer: --quit-after expects seconds (> 0), got '" << v << "'\n";
        return false;
      }
      o.quit_after_s = s;
    } else if (a == "--frames") {
      if (!value(v)) return false;
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end != '\0' || n < 1 || n > 100000) {
        std::cerr << "laptrainer: --frames expects a whole number from 1 to 100000, got '" << v
                  << "'\n";
        return false;
      }
      o.frames = static_cast<int>(n);
    } else if (a == "--size") {
      if (!value(v)) return false;
      int w = 0;
      int h = 0;
      char x = 0;
      char rest = 0;
      if (std::sscanf(v.c_str(), "%d%c%d%c", &w, &x, &h, &rest) != 3 || x != 'x' || w < 160 ||
          w > 7680 || h < 120 || h > 4320) {
        std::cerr << "laptrainer: --size expects WIDTHxHEIGHT in pixels (160x120 to 7680x4320), "
                     "got '"
                  << v << "'\n";
        return false;
      }
      o.field_width = w;
      o.field_height = h;
    } else if (a == "--render-quality") {
      if (!value(v)) return false;
      o.render_quality = lap::app::parse_render_quality(QString::fromStdString(v));
      if (!o.render_quality) {
        std::cerr << "laptrainer: --render-quality expects auto, full or fast, got '" << v << "'\n";
        return false;
      }
    } else if (a == "--no-hud") {
      o.hud = false;
    } else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else {
      std::cerr << "laptrainer: unknown argument '" << a << "'\n";
      return false;
    }
  }
  return true;
}

bool display_available() {
  const char* platform = std::getenv("QT_QPA_PLATFORM");
  if (platform != nullptr && std::strncmp(platform, "offscreen", 9) == 0) return false;
  const char* x = std::getenv("DISPLAY");
  return x != nullptr && *x != '\0';
}

int run_headless(const std::string& scenario) {
  std::cout << "laptrainer: no display available (DISPLAY is not set); running the scenario "
               "headless instead of opening the window.\n"
               "  To see the window, run on a desktop session or under Xvfb: xvfb-run -a "
               "laptrainer\n";
  const lap::sim::SceneLoadResult r = lap::sim::load_scene_file(scenario);
  if (!r.ok()) {
    for (const auto& p : r.diagnostics()) std::cerr << p.to_string() << "\n";
    return kExitProblems;
  }
  std::cout << lap::sim::describe_scene(r.value());
  std::cout << "headless run finished: scene loaded and every organ mesh is a closed, oriented "
               "manifold.\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const double started_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  Options opt;
  if (!parse(argc, argv, opt)) {
    std::cerr << kUsage;
    return kExitUsage;
  }
  if (opt.scenario.empty()) opt.scenario = lap::sim::default_scenario_path().string();
  if (!opt.stats.empty()) {
    // Said now, not after the session: the statistics' file must be writable.
    std::ofstream probe(opt.stats, std::ios::app);
    if (!probe) {
      std::cerr << "laptrainer: --stats " << opt.stats << ": cannot write there ("
                << std::strerror(errno) << ")\n";
      return kExitProblems;
    }
  }

  if (!display_available()) {
    if (opt.review) {
      std::cerr << "laptrainer: --review needs a display (DISPLAY is not set); the headless "
                   "report is laptrainer-cli report --session DIR\n";
      return kExitProblems;
    }
    if (!opt.screenshot.empty()) {
      std::cerr << "laptrainer: --screenshot needs a display (DISPLAY is not set); run it under "
                   "xvfb-run -a\n";
      return kExitProblems;
    }
    return run_headless(opt.scenario);
  }

  // VTK renders into the widget's native window with its own OpenGL context.
  QApplication::setAttribute(Qt::AA_NativeWindows, false);
  QApplication app(argc, argv);
  QApplication::setApplicationName("laptrainer");
  QApplication::setApplicationDisplayName("laptrainer");
  lap::app::apply_application_style(app);
  if (opt.review) {
    // The instructor's review as its own mode (app/review/README.md).
    lap::Result<lap::app::ReviewWindow*> review =
        lap::app::ReviewWindow::open_default(QString::fromStdString(opt.trainee));
    if (!review.ok()) {
      std::cerr << "laptrainer: " << review.message() << "\n";
      return kExitProblems;
    }
    review.value()->show();
    return QApplication::exec();
  }
  lap::app::MainWindow window;
  window.set_record_dir(QString::fromStdString(opt.record));
  window.set_devices(opt.devices);
  if (opt.render_quality) window.set_render_quality(*opt.render_quality, /*remember=*/false);
  if (opt.field_width > 0) {
    window.operative_view()->setFixedSize(opt.field_width, opt.field_height);
  }
  window.operative_view()->set_hud_shown(opt.hud);
  if (opt.names_session) {
    if (const lap::Status opened = window.open_scenario(QString::fromStdString(opt.scenario));
        !opened.ok()) {
      std::cerr << opened.message() << "\n";
      if (!opt.screenshot.empty()) return kExitProblems;
    }
  }
  window.show();

  if (!opt.screenshot.empty()) {
    // Render the requested number of frames through the event loop, then write the last one.
    auto* timer = new QTimer(&window);
    QObject::connect(timer, &QTimer::timeout, &window, [&window, &opt, timer] {
      // (A session that ended before then shows its result: the field's last frame is taken.)
      if (window.view()->frames() < opt.frames &&
          window.step() == lap::app::MainWindow::Step::kRun) {
        window.view()->render();
        return;
      }
      timer->stop();
      const lap::Status shot = window.view()->save_png(QString::fromStdString(opt.screenshot));
      bool ok = shot.ok();
      if (!ok) std::cerr << "laptrainer: " << shot.message() << "\n";
      if (const lap::Status ended = window.end_session(); !ended.ok()) {
        std::cerr << "laptrainer: " << ended.message() << "\n";
        ok = false;
      }
      QApplication::exit(ok ? 0 : 1);
    });
    timer->start(0);
  }
  if (opt.quit_after_s > 0.0) {
    QTimer::singleShot(static_cast<int>(opt.quit_after_s * 1000.0), &window,
                       [&window] { window.close(); });
  }
  const int code = QApplication::exec();
  if (!opt.stats.empty()) {
    // The window has ended its session by now (closing it, or the screenshot's end).
    if (const lap::Status ended = window.end_session(); !ended.ok()) {
      std::cerr << "laptrainer: " << ended.message() << "\n";
    }
    const std::vector<double>& frames = window.view()->frame_times_s();
    const double first_frame_s = frames.empty() ? -1.0 : frames.front() - started_s;
    std::ofstream f(opt.stats);
    nlohmann::ordered_json stats =
        lap::app::run_stats_json(frames, first_frame_s, window.last_metrics());
    // What the frames were drawn with: the renderer and the picture's profile.
    const lap::app::RenderProfile& profile = window.operative_view()->render_profile_in_use();
    stats["graphics"]["renderer"] = window.view()->gl_renderer();
    stats["graphics"]["render_quality"] = profile.fast ? "fast" : "full";
    stats["graphics"]["scene_scale"] = window.view()->drawn_scene_scale();
    f << stats.dump(2) << "\n";
    f.flush();
    if (!f) {
      std::cerr << "laptrainer: " << opt.stats << ": cannot write the statistics\n";
      return code == 0 ? kExitProblems : code;
    }
  }
  return code;
}
