// The scenario author's dock in the real window (app/authoring/authoring_panel.h), driven with
// Qt Test's events under xvfb-run: a scenario with an error lists it as file:line and a click
// shows that line; fixed on disk, it reloads by itself and the problem is gone; a stiffness
// typed into the panel reaches the running session's haptic loop; "Save to scenario" changes
// that one line of the file. With LAP_SCREENSHOT_DIR set, the panel is saved there as
// authoring.png (and authoring-problems.png).

#include <gtest/gtest.h>

#include <QApplication>
#include <QTest>
#include <fstream>
#include <sstream>

#include "app/main_window.h"
#include "haptics/setup/mesh_generators.h"
#include "sim/setup/mesh_loader.h"
#include "tests/test_support.h"

namespace lap::app {
namespace {

namespace fs = std::filesystem;

using test::lines_of;
using test::read_file;

// A slab and two probes; `stiffness` as written (line 9).
std::string scenario(const std::string& stiffness) {
  return R"(# A slab for the authoring panel's test.
version: 1
name: authoring slab
organs:
  - name: slab
    mesh: slab.obj
    transform: {translation_m: [0, -0.005, 0]}
    material:
      stiffness_n_per_m: )" +
         stiffness + R"(   # estimate, for the test
      damping_n_s_per_m: 0.5        # estimate
      friction_static: 0.3
      friction_dynamic: 0.2

trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: probe}
)";
}

void write(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
}

void save_shot(QWidget* w, const char* name) {
  const char* dir = std::getenv("LAP_SCREENSHOT_DIR");
  if (dir == nullptr) return;
  EXPECT_TRUE(w->grab().save(QString(dir) + "/" + name));
}

TEST(AuthoringPanel, ProblemsReloadLiveTuningAndSave) {
  const test::TempDir dir;
  ASSERT_TRUE(
      sim::save_obj(haptics::make_box({0.06, 0.01, 0.06}, 6), dir.path() / "slab.obj").ok());
  const fs::path file = dir.path() / "slab.yaml";
  write(file, scenario("-5"));

  MainWindow window;
  window.resize(1400, 900);
  window.show();
  AuthoringPanel* panel = window.authoring_panel();
  ASSERT_NE(panel, nullptr);
  panel->show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  panel->open(QString::fromStdString(file.string()));

  // The loader's problem, as file:line: field: message.
  ASSERT_GE(panel->problems()->count(), 1);
  const QString problem = panel->problems()->item(0)->text();
  EXPECT_TRUE(problem.startsWith(
      QString::fromStdString(file.string() + ":9: organs[0].material.stiffness_n_per_m")))
      << problem.toStdString();
  EXPECT_EQ(panel->organs()->count(), 0);
  // A click shows its line.
  const QRect rect = panel->problems()->visualItemRect(panel->problems()->item(0));
  QTest::mouseClick(panel->problems()->viewport(), Qt::LeftButton, {}, rect.center());
  EXPECT_EQ(panel->location()->text(), QString::fromStdString(file.string() + ":9"));
  EXPECT_EQ(panel->source()->textCursor().blockNumber(), 8);
  save_shot(panel, "authoring-problems.png");

  // Fixed on disk: the watcher reloads it, the problem is gone, the session runs.
  bool reloaded_ok = false;
  QObject::connect(panel, &AuthoringPanel::reloaded, [&](bool ok) { reloaded_ok = ok; });
  write(file, scenario("200"));
  EXPECT_TRUE(QTest::qWaitFor([&] { return reloaded_ok; }, 5000));
  EXPECT_EQ(panel->problems()->count(), 0);
  ASSERT_EQ(panel->organs()->count(), 1);
  sim::Session* session = window.operative_view()->session().session();
  ASSERT_NE(session, nullptr);
  EXPECT_EQ(panel->stiffness()->value(), 200.0);

  // Typed into the panel: the haptic loop renders it at its next tick.
  const std::string before = read_file(file);
  panel->stiffness()->setFocus();
  panel->stiffness()->selectAll();
  QTest::keyClicks(panel->stiffness(), "400");
  QTest::keyClick(panel->stiffness(), Qt::Key_Enter);
  EXPECT_EQ(panel->stiffness()->value(), 400.0);
  EXPECT_TRUE(QTest::qWaitFor(
      [&] { return session->surface_tunings_taken() == session->surface_tunings_posted(); }, 2000));
  EXPECT_GE(session->surface_tunings_posted(), 1U);
  EXPECT_EQ(session->surface_parameters(0).stiffness_n_per_m, 400.0);
  EXPECT_EQ(session->surface_parameters(0).damping_n_s_per_m, 0.5);
  EXPECT_EQ(session->surface_parameters(0).friction_static, 0.3);
  save_shot(panel, "authoring.png");

  // Saved: only the stiffness line differs, its comment kept.
  QTest::mouseClick(panel->save_button(), Qt::LeftButton);
  const std::vector<std::string> a = lines_of(before);
  const std::vector<std::string> b = lines_of(read_file(file));
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    if (i == 8) {
      EXPECT_EQ(b[i], "      stiffness_n_per_m: 400   # estimate, for the test");
    } else {
      EXPECT_EQ(a[i], b[i]) << "line " << i + 1;
    }
  }
  // The save is a change on disk too: it reloads with the saved value, no problem.
  reloaded_ok = false;
  EXPECT_TRUE(QTest::qWaitFor([&] { return reloaded_ok; }, 5000));
  EXPECT_EQ(panel->problems()->count(), 0);
  EXPECT_EQ(panel->stiffness()->value(), 400.0);
  window.close();
}

}  // namespace
}  // namespace lap::app

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
