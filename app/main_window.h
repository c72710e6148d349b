#pragma once
/// \file
/// The trainee's main window: menus File/View/Help, a status bar, and the 3D view of the scene.

#include <QLabel>
#include <QMainWindow>
#include <QString>
#include <memory>

#include "app/live_session.h"
#include "app/tool_actors.h"
#include "app/vtk_view.h"
#include "hardware/space_mouse.h"
#include "sim/setup/scene.h"

namespace lap::app {

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  MainWindow();
  /// Loads a scenario and shows it; on failure keeps the current scene and returns the problems.
  [[nodiscard]] Status open_scenario(const QString& file);
  VtkView* view() { return view_; }
  /// The last session's metrics, once end_session() or the window's closing has stopped it.
  [[nodiscard]] const sim::SessionMetrics& last_metrics() const { return session_.last_metrics(); }
  /// Where the session's inputs and metrics are saved when it ends (window closed, quit);
  /// empty: not saved unless the user asks (File > End and Save Session).
  void set_record_dir(const QString& dir) { record_dir_ = dir; }
  /// The devices the next session uses (default: two simulated tools).
  void set_devices(const std::array<hardware::DeviceSpec, 2>& devices) { devices_ = devices; }
  /// Ends the running session: saved to the record folder if one is set; the diagnostics say
  /// why saving failed.
  Status end_session();

 protected:
  void keyPressEvent(QKeyEvent* event) override;
  void closeEvent(QCloseEvent* event) override;

 private:
  void show_scene(const sim::Scene& scene);
  void update_loops();
  void open_dialog();
  void screenshot_dialog();
  void save_session_dialog();
  void update_status();

  VtkView* view_ = nullptr;
  QLabel* scene_label_ = nullptr;
  QLabel* fps_label_ = nullptr;
  QLabel* loops_label_ = nullptr;
  LiveSession session_;
  SessionActors actors_;
  int active_tool_ = 0;
  int64_t last_haptic_tick_ = -1;
  int64_t last_model_steps_ = 0;
  sim::Scene scene_;
  bool wireframe_ = false;
  QString record_dir_;
  std::array<hardware::DeviceSpec, 2> devices_{};
  // A 3D mouse, when spacenavd and libspnav are there: it steers the active tool like the keys.
  std::unique_ptr<hardware::SpaceMouse> space_mouse_;
  hardware::SpaceMouseMapping space_mouse_mapping_;
};

}  // namespace lap::app
