// The scenario author's dock in the real window (app/authoring/authoring_panel.h), driven with
// Qt Test's events under xvfb-run: a scenario with an error lists it as file:line and a click
// shows that line; fixed on disk, it reloads by itself and the problem is gone; a stiffness
// typed into the panel reaches the running session's haptic loop; "Save to scenario" changes
// that one line of the file; shading switched off and a texture's height changed reach the
// session and the file too. With LAP_SCREENSHOT_DIR set, the panel is saved there as
// authoring.png (and authoring-problems.png, authoring-shading.png, authoring-texture.png).

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

// The window shown with its authoring dock, `file` opened there; null if the window did not show.
AuthoringPanel* open_in_window(MainWindow* window, const fs::path& file) {
  window->resize(1400, 900);
  window->show();
  AuthoringPanel* panel = window->authoring_panel();
  if (panel == nullptr || !QTest::qWaitForWindowExposed(window)) return nullptr;
  panel->show();
  panel->open(QString::fromStdString(file.string()));
  return panel;
}

TEST(AuthoringPanel, ProblemsReloadLiveTuningAndSave) {
  const test::TempDir dir;
  ASSERT_TRUE(
      sim::save_obj(haptics::make_box({0.06, 0.01, 0.06}, 6), dir.path() / "slab.obj").ok());
  const fs::path file = dir.path() / "slab.yaml";
  write(file, scenario("-5"));

  MainWindow window;
  AuthoringPanel* panel = open_in_window(&window, file);
  ASSERT_NE(panel, nullptr);

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

// A shaded ball and a textured slab: the panel switches the ball's force shading off and halves
// the slab's texture, each reaching the running session's haptic loop, and the save writes them
// into the file (the one-line flow map edited in place, the block's amplitude line with its
// comment), nothing else changed.
TEST(AuthoringPanel, ShadingAndTextureChangedInThePanelReachTheSessionAndTheFile) {
  const test::TempDir dir;
  ASSERT_TRUE(sim::save_obj(haptics::make_uv_sphere(0.02, 8, 12), dir.path() / "ball.obj").ok());
  ASSERT_TRUE(
      sim::save_obj(haptics::make_box({0.06, 0.01, 0.06}, 6), dir.path() / "slab.obj").ok());
  const fs::path file = dir.path() / "surfaces.yaml";
  write(file, R"(# A shaded ball and a textured slab.
version: 1
name: authoring surfaces
organs:
  - name: ball
    mesh: ball.obj
    transform: {translation_m: [-0.04, 0.02, 0]}
    material:
      stiffness_n_per_m: 200
      shading: {enabled: true, crease_angle_deg: 40}
  - name: slab
    mesh: slab.obj
    transform: {translation_m: [0.04, -0.005, 0]}
    material:
      stiffness_n_per_m: 300
      texture:
        kind: procedural
        function: fourier
        amplitude_m: 0.0005   # estimate, for the test
        wavelength_m: 0.005
trocars:
  - {name: pl, position_m: [-0.15, 0.12, 0.0]}
  - {name: pr, position_m: [0.0, 0.15, 0.0]}
tools:
  - {name: l, side: left, trocar: pl, kind: probe}
  - {name: r, side: right, trocar: pr, kind: probe}
)");
  MainWindow window;
  AuthoringPanel* panel = open_in_window(&window, file);
  ASSERT_NE(panel, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&] { return panel->organs()->count() == 2; }, 5000));
  EXPECT_EQ(panel->problems()->count(), 0);
  sim::Session* session = window.operative_view()->session().session();
  ASSERT_NE(session, nullptr);
  const auto taken = [&] {
    return QTest::qWaitFor(
        [&] { return session->surface_tunings_taken() == session->surface_tunings_posted(); },
        2000);
  };
  const auto pick = [&](int row) {
    panel->follow_touch()->setChecked(false);
    const QRect r = panel->organs()->visualItemRect(panel->organs()->item(row));
    QTest::mouseClick(panel->organs()->viewport(), Qt::LeftButton, {}, r.center());
  };

  // The ball: shaded, its shading can be switched; the texture's height cannot (it has none).
  pick(0);
  EXPECT_TRUE(panel->shading()->isEnabled());
  EXPECT_TRUE(panel->shading()->isChecked());
  EXPECT_FALSE(panel->texture_mm()->isEnabled());
  EXPECT_TRUE(session->surface_parameters(0).shading);
  panel->shading()->setFocus();
  QTest::keyClick(panel->shading(), Qt::Key_Space);
  EXPECT_FALSE(panel->shading()->isChecked());
  EXPECT_TRUE(taken());
  EXPECT_FALSE(session->surface_parameters(0).shading);
  save_shot(panel, "authoring-shading.png");

  // The slab: its texture 0.5 mm high, typed down to 0.25 mm: rendered at half its height.
  pick(1);
  ASSERT_TRUE(panel->texture_mm()->isEnabled());
  EXPECT_DOUBLE_EQ(panel->texture_mm()->value(), 0.5);
  panel->texture_mm()->setFocus();
  panel->texture_mm()->selectAll();
  QTest::keyClicks(panel->texture_mm(), "0.25");
  QTest::keyClick(panel->texture_mm(), Qt::Key_Enter);
  EXPECT_TRUE(taken());
  EXPECT_DOUBLE_EQ(session->surface_parameters(1).texture_scale, 0.5);
  EXPECT_TRUE(session->surface_parameters(0).stiffness_n_per_m == 200.0);
  save_shot(panel, "authoring-texture.png");

  const std::vector<std::string> before = lines_of(read_file(file));
  QTest::mouseClick(panel->save_button(), Qt::LeftButton);
  const std::vector<std::string> after = lines_of(read_file(file));
  ASSERT_EQ(before.size(), after.size());
  for (size_t i = 0; i < before.size(); ++i) {
    if (i == 9) {
      EXPECT_EQ(after[i], "      shading: {enabled: false, crease_angle_deg: 40}");
    } else if (i == 18) {
      // One character longer: the comment keeps its column.
      EXPECT_EQ(after[i], "        amplitude_m: 0.00025  # estimate, for the test");
    } else {
      EXPECT_EQ(before[i], after[i]) << "line " << i + 1;
    }
  }
  window.close();
}

}  // namespace
}  // namespace lap::app

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
