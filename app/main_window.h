#pragma once
/// \file
/// The trainee's window: a training session from sign-in to result, one page at a time —
/// sign in, choose a patient, set up the instruments, the briefing, the run, the result — with
/// the desktop's menus (File, View, Session, Help) and shortcuts, and a status bar with the
/// loops' figures while a session runs.
///
/// Each attempt is saved under the user's data folder as it runs (session_archive.h: streamed,
/// so that a crash leaves it reviewable) and filed in the session database when it ends; the
/// result page shows it beside the trainee's earlier attempts on the same patient. What the
/// station remembers (trainee, patient, devices, window) is in station_settings.h.
///
/// Started with options that name a session (laptrainer --scenario, --left, --right, --record,
/// --screenshot: main.cpp), the window skips sign-in and runs that session at once
/// (open_scenario): it is saved where --record says, and filed nowhere.

#include <QLabel>
#include <QMainWindow>
#include <QStackedWidget>
#include <QString>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "app/authoring/authoring_panel.h"
#include "app/operative_view.h"
#include "app/pages/briefing_page.h"
#include "app/pages/devices_page.h"
#include "app/pages/result_page.h"
#include "app/pages/run_page.h"
#include "app/pages/scenario_page.h"
#include "app/pages/sign_in_page.h"
#include "app/render_quality.h"
#include "app/scenario_catalog.h"
#include "app/session_archive.h"
#include "app/station_settings.h"
#include "app/store/session_store.h"
#include "app/vtk_view.h"
#include "sim/setup/scene.h"

class QAction;

namespace lap::app {

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  /// The pages, in the order a session goes through them.
  enum class Step { kSignIn, kScenario, kDevices, kBriefing, kRun, kResult };

  MainWindow();
  ~MainWindow() override;
  MainWindow(const MainWindow&) = delete;
  MainWindow& operator=(const MainWindow&) = delete;
  MainWindow(MainWindow&&) = delete;
  MainWindow& operator=(MainWindow&&) = delete;

  /// Runs a session on `file` at once (the command line's session: no sign-in, not filed), with
  /// the devices set_devices() gave; on failure keeps the current page and returns the problems.
  [[nodiscard]] Status open_scenario(const QString& file);
  VtkView* view() { return run_->operative()->view(); }
  OperativeView* operative_view() { return run_->operative(); }
  /// How the operative field is drawn (render_quality.h); `remember`: kept for later runs.
  void set_render_quality(RenderQualityChoice choice, bool remember);
  /// The scenario author's dock (Authoring > Authoring Mode shows it).
  AuthoringPanel* authoring_panel() { return authoring_; }
  /// The last session's metrics, once end_session() or the window's closing has stopped it.
  [[nodiscard]] const sim::SessionMetrics& last_metrics() const {
    return run_->operative()->session().last_metrics();
  }
  /// Where the command line's session is saved (streamed while it runs, completed when it
  /// ends); empty: not saved.
  void set_record_dir(const QString& dir) { record_dir_ = dir; }
  /// The devices of the command line's session (default: two keyboard-driven tools).
  void set_devices(const std::array<hardware::DeviceSpec, 2>& devices) { cli_devices_ = devices; }
  /// Sessions with scripted or replayed devices only run in lockstep, as fast as the computer
  /// can (LiveSessionOptions::fast); for tests and demonstrations.
  void set_fast_playback(bool on) { fast_playback_ = on; }
  /// Ends the running session: an attempt is saved and filed, the command line's saved where
  /// --record says; the diagnostics say why saving failed.
  Status end_session();

  [[nodiscard]] Step step() const { return step_; }
  [[nodiscard]] SignInPage* sign_in_page() { return sign_in_; }
  [[nodiscard]] ScenarioPage* scenario_page() { return scenarios_; }
  [[nodiscard]] DevicesPage* devices_page() { return devices_; }
  [[nodiscard]] BriefingPage* briefing_page() { return briefing_; }
  [[nodiscard]] RunPage* run_page() { return run_; }
  [[nodiscard]] ResultPage* result_page() { return result_; }
  /// The attempt running or last ended (empty uuid: none).
  [[nodiscard]] const SessionRow& attempt() const { return attempt_; }
  [[nodiscard]] const QString& trainee() const { return trainee_; }
  /// The session database (null when it could not be opened: store_problem() says why).
  [[nodiscard]] SessionStore* store() { return store_.get(); }
  [[nodiscard]] const QString& store_problem() const { return store_problem_; }

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  void build_menus();
  void build_step_bar();
  void go(Step step);
  void update_actions();
  void sign_in(const QString& trainee);
  void sign_out();
  void show_scenarios();
  void choose_scenario(const CatalogEntry& entry);
  void open_scenario_dialog();
  void devices_chosen(const std::array<QString, 2>& specs, int dominant_hand);
  void start_attempt();
  void restart_attempt();
  void attempt_ended();
  void end_attempt_by_trainee();
  /// Stops the running session and saves it; for an attempt also files it and returns its
  /// report (metrics.json's JSON). `show` goes to the result page.
  Status finish_session(bool show);
  void screenshot_dialog();
  void toggle_full_screen();
  void show_controls();
  void update_status();
  void file_unfiled_attempts();
  /// The signed-in trainee's attempts on `scenario_file`, newest first; `why` says why none
  /// could be read.
  [[nodiscard]] std::vector<SessionRow> attempts_on(const QString& scenario_file,
                                                    QString* why) const;
  [[nodiscard]] QStringList known_trainees() const;
  [[nodiscard]] Status file(const SessionRow& record);
  [[nodiscard]] std::array<hardware::DeviceSpec, 2> parsed_devices() const;

  StationSettings settings_;
  std::unique_ptr<SessionStore> store_;
  QString store_problem_;
  QStackedWidget* stack_ = nullptr;
  QWidget* step_bar_ = nullptr;
  std::vector<QLabel*> step_labels_;
  QLabel* trainee_label_ = nullptr;
  SignInPage* sign_in_ = nullptr;
  ScenarioPage* scenarios_ = nullptr;
  DevicesPage* devices_ = nullptr;
  BriefingPage* briefing_ = nullptr;
  RunPage* run_ = nullptr;
  ResultPage* result_ = nullptr;
  AuthoringPanel* authoring_ = nullptr;
  QLabel* scene_label_ = nullptr;
  QLabel* fps_label_ = nullptr;
  QLabel* loops_label_ = nullptr;
  QAction* pause_action_ = nullptr;
  QAction* restart_action_ = nullptr;
  QAction* end_action_ = nullptr;
  QAction* home_action_ = nullptr;
  QAction* reset_camera_action_ = nullptr;
  QAction* full_screen_action_ = nullptr;
  std::array<QAction*, 3> quality_actions_{};  // auto, full, fast
  QAction* sign_out_action_ = nullptr;
  QAction* choose_action_ = nullptr;
  QAction* devices_action_ = nullptr;

  Step step_ = Step::kSignIn;
  QString trainee_;
  CatalogEntry scenario_;
  std::optional<sim::Scene> scene_;
  std::array<QString, 2> device_texts_{"simulated", "simulated"};
  int dominant_hand_ = 1;
  SessionRow attempt_;            ///< the attempt running or last ended
  bool attempt_running_ = false;  ///< attempt_ is the running session's
  bool direct_ = false;           ///< the command line's session
  bool wireframe_ = false;
  bool fast_playback_ = false;
  QString record_dir_;
  std::array<hardware::DeviceSpec, 2> cli_devices_{};
};

}  // namespace lap::app
