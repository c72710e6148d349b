#pragma once
/// \file
/// The scenario author's dock (issue 26, "Developers loading new organ scenarios"): opens any
/// scenario through the window, lists its problems (`file:line: field: message`; a click shows
/// that line of the file), reloads it when the file changes on disk, and tunes each organ's
/// haptic surface live — stiffness, damping, static and dynamic friction, force shading, texture
/// height — through the running session's mailbox (sim/runtime/surface_tuning.h), so the tool
/// touching the organ feels each change at the next haptic tick. "Save to scenario" writes the
/// changed values back into the YAML file, comments and layout kept
/// (sim/authoring/scenario_editor.h).

#include <QCheckBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileSystemWatcher>
#include <QLabel>
#include <QListWidget>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QSlider>
#include <QTimer>
#include <functional>
#include <vector>

#include "core/result.h"
#include "sim/runtime/session.h"
#include "sim/setup/scenario.h"

namespace lap::app {

class AuthoringPanel : public QDockWidget {
  Q_OBJECT

 public:
  /// Loads and shows a scenario (the window's open_scenario): its problems when it cannot.
  using Opener = std::function<Status(const QString& file)>;
  /// The running session whose surfaces are tuned; null when none runs.
  using SessionSource = std::function<sim::Session*()>;

  AuthoringPanel(Opener opener, SessionSource session, QWidget* parent = nullptr);

  /// Opens `file` (through the opener), lists its problems, watches it for changes.
  void open(const QString& file);
  /// Opens the watched file again (as a change on disk does).
  void reload();
  /// Writes every value changed since the file was loaded back into it; the problems list says
  /// why not.
  Status save();
  [[nodiscard]] const QString& file() const { return file_; }

  // The widgets, for the GUI tests.
  QListWidget* problems() { return problems_; }
  QPlainTextEdit* source() { return source_; }
  QLabel* location() { return location_; }
  QListWidget* organs() { return organs_; }
  QDoubleSpinBox* stiffness() { return stiffness_; }
  QSlider* stiffness_slider() { return stiffness_slider_; }
  QDoubleSpinBox* damping() { return damping_; }
  QDoubleSpinBox* friction_static() { return friction_static_; }
  QDoubleSpinBox* friction_dynamic() { return friction_dynamic_; }
  QCheckBox* shading() { return shading_; }
  QDoubleSpinBox* texture_mm() { return texture_mm_; }
  QPushButton* save_button() { return save_button_; }
  QCheckBox* follow_touch() { return follow_touch_; }
  /// Selects the organ a tool touches now, when "follow the touched organ" is on (a timer calls
  /// it ten times a second).
  void follow_touched_organ();

 signals:
  /// The file was (re)opened: `ok` when it loaded and its session runs.
  void reloaded(bool ok);

 private:
  /// What the author changed of an organ, field by field (only those are saved).
  enum Field : unsigned {
    kStiffness = 1,
    kDamping = 2,
    kFrictionStatic = 4,
    kFrictionDynamic = 8,
    kShading = 16,
    kTexture = 32,
  };
  struct OrganTuning {
    sim::SurfaceParameters parameters;
    double texture_amplitude_m = 0.0;  ///< as the author set it (saved as it reads)
    unsigned changed = 0;
  };
  void show_problems(const std::vector<Diagnostic>& problems);
  void show_line(int line);
  void select_organ(int organ);
  void widget_changed(Field field);
  void post(int organ);
  void watch();
  void file_changed();

  Opener open_;
  SessionSource session_;
  QString file_;
  sim::Scenario scenario_;  ///< as the file had it when it loaded
  std::vector<OrganTuning> tunings_;
  int organ_ = -1;
  bool updating_ = false;  ///< widgets being set from the state, not by the author
  QFileSystemWatcher watcher_;
  QTimer reload_timer_;  ///< a burst of changes (an editor's save) reloads once
  QTimer retry_timer_;   ///< posts a tuning again while the mailbox was full
  QTimer touch_timer_;   ///< follows the touched organ

  QLabel* file_label_ = nullptr;
  QListWidget* problems_ = nullptr;
  QLabel* location_ = nullptr;
  QPlainTextEdit* source_ = nullptr;
  QListWidget* organs_ = nullptr;
  QCheckBox* follow_touch_ = nullptr;
  QDoubleSpinBox* stiffness_ = nullptr;
  QSlider* stiffness_slider_ = nullptr;
  QDoubleSpinBox* damping_ = nullptr;
  QDoubleSpinBox* friction_static_ = nullptr;
  QDoubleSpinBox* friction_dynamic_ = nullptr;
  QCheckBox* shading_ = nullptr;
  QDoubleSpinBox* texture_mm_ = nullptr;
  QPushButton* save_button_ = nullptr;
  QLabel* status_ = nullptr;
  std::vector<int> pending_;  ///< organs whose last tuning the mailbox refused
};

}  // namespace lap::app
