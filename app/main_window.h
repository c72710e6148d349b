#pragma once
/// \file
/// The trainee's main window: menus File/View/Help, a status bar, and the 3D view of the scene.

#include <QLabel>
#include <QMainWindow>
#include <QString>
#include <memory>

#include "app/authoring/authoring_panel.h"
#include "app/operative_view.h"
#include "app/vtk_view.h"
#include "sim/setup/scene.h"

namespace lap::app {

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  MainWindow();
  /// Loads a scenario and shows it; on failure keeps the current scene and returns the problems.
  [[nodiscard]] Status open_scenario(const QString& file);
  VtkView* view() { return operative_->view(); }
  /// The scenario author's dock (Authoring > Authoring Mode shows it).
  AuthoringPanel* authoring_panel() { return authoring_; }
  OperativeView* operative_view() { return operative_; }
  /// The last session's metrics, once end_session() or the window's closing has stopped it.
  [[nodiscard]] const sim::SessionMetrics& last_metrics() const {
    return operative_->session().last_metrics();
  }
  /// Where the session's inputs and metrics are saved when it ends (window closed, quit);
  /// empty: not saved unless the user asks (File > End and Save Session).
  void set_record_dir(const QString& dir) { record_dir_ = dir; }
  /// The devices the next session uses (default: two simulated tools).
  void set_devices(const std::array<hardware::DeviceSpec, 2>& devices) { devices_ = devices; }
  /// Ends the running session: saved to the record folder if one is set; the diagnostics say
  /// why saving failed.
  Status end_session();

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void show_scene(const sim::Scene& scene);
  void open_dialog();
  void screenshot_dialog();
  void save_session_dialog();
  void update_status();

  OperativeView* operative_ = nullptr;
  AuthoringPanel* authoring_ = nullptr;
  QLabel* scene_label_ = nullptr;
  QLabel* fps_label_ = nullptr;
  QLabel* loops_label_ = nullptr;
  sim::Scene scene_;
  bool wireframe_ = false;
  QString record_dir_;
  std::array<hardware::DeviceSpec, 2> devices_{};
};

}  // namespace lap::app
