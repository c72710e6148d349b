#pragma once
/// \file
/// The instructor's review (issue 24), a top-level window of its own: trainees and their
/// sessions from the training-record database (app/store) — filtered by result, searched,
/// sorted by any column; per session its result and reasons, each metric with its value as
/// stored and as replayed and its pass/fail against the scenario's proficiency benchmarks, the
/// plots (force on the duct with the injury threshold, tool speeds, insertion depth, the task's
/// events) and the 3D replay with its transport, the plots' cursor following the replay; per
/// trainee the learning curve of each metric with the experts' band, and the cohort's curves.
/// Exports: the session's metrics (CSV), raw series (CSV), the whole session (JSON), the
/// session's and the trainee's PDF reports, the trainee's metrics over sessions (CSV).
///
/// Access follows the store's: opened for a trainee it shows their sessions only; an instructor
/// who signs in (Sign in…) sees everyone's and the cohort.
///
/// A session's plots and 3D frames come from replaying its recording (sim::ReplayTimeline) on a
/// worker thread when the session is selected; the metrics as stored show at once.

#include <QMainWindow>
#include <QString>
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "app/store/session_store.h"
#include "core/result.h"
#include "sim/report/replay_timeline.h"
#include "sim/setup/scenario.h"

class QChart;
class QChartView;
class QComboBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QSortFilterProxyModel;
class QStandardItemModel;
class QTabWidget;
class QTableView;
class QTableWidget;

namespace lap::app {

class ReplayPlayer;
class SessionCharts;

class ReviewWindow : public QMainWindow {
  Q_OBJECT

 public:
  /// The metrics table's columns: what the trainee is judged on first (the verdict and its
  /// limit), then the value as stored and as the replay recomputed it.
  enum MetricColumn { kMetricName, kMetricVerdict, kMetricLimit, kMetricStored, kMetricReplayed };

  /// Reviews `store`'s sessions as `viewer` may see them; `store` outlives the window.
  ReviewWindow(SessionStore* store, Viewer viewer, QWidget* parent = nullptr);
  /// The same over a store the window keeps.
  ReviewWindow(std::unique_ptr<SessionStore> store, Viewer viewer, QWidget* parent = nullptr);
  /// Opens the station's store (SessionStore::open_default) and a review window over it for
  /// `trainee` ("" : nobody yet — an instructor signs in), deleted when closed. The trainee
  /// window's menu action calls this.
  [[nodiscard]] static Result<ReviewWindow*> open_default(const QString& trainee);
  ~ReviewWindow() override;
  ReviewWindow(const ReviewWindow&) = delete;
  ReviewWindow& operator=(const ReviewWindow&) = delete;

  /// Reads the trainees and sessions again (the status bar says why when it cannot).
  Status reload();
  [[nodiscard]] const Viewer& viewer() const { return viewer_; }
  /// Signs an instructor in (everyone's sessions, the cohort); the window's viewer otherwise.
  Status sign_in(const QString& name, const QString& password);
  /// Back to the viewer the window was opened for.
  void sign_out();

  /// Shows one trainee's sessions ("" : everyone the viewer may see).
  void select_trainee(const QString& name);
  /// Selects a session in the table (false: not listed) and starts its replay.
  bool select_session(const QString& uuid);
  /// The selected session's replay has finished (successfully or not: replay_status()).
  [[nodiscard]] bool replay_ready() const { return replay_done_; }
  [[nodiscard]] QString replay_status() const;
  [[nodiscard]] std::shared_ptr<const sim::ReplayTimeline> timeline() const { return timeline_; }

  // Exports of the selected session and trainee to `file`.
  Status export_session_metrics_csv(const QString& file);
  Status export_series_csv(const QString& file);
  Status export_session_json(const QString& file);
  Status export_session_pdf(const QString& file);
  /// The selected (else the session's) trainee, over their sessions of the selected session's
  /// scenario.
  Status export_trainee_pdf(const QString& file);
  Status export_trainee_csv(const QString& file);

  // The widgets, for the GUI tests.
  [[nodiscard]] QListWidget* trainee_list() const { return trainees_; }
  [[nodiscard]] QTableView* session_table() const { return table_; }
  [[nodiscard]] QLineEdit* search_box() const { return search_; }
  [[nodiscard]] QComboBox* result_filter() const { return result_filter_; }
  [[nodiscard]] QTableWidget* metrics_table() const { return metrics_; }
  [[nodiscard]] SessionCharts* charts() const { return charts_; }
  [[nodiscard]] ReplayPlayer* player() const { return player_; }
  [[nodiscard]] QTabWidget* tabs() const { return tabs_; }
  [[nodiscard]] QComboBox* curve_metric_box() const { return curve_metric_; }
  [[nodiscard]] QComboBox* cohort_metric_box() const { return cohort_metric_; }
  [[nodiscard]] QChart* learning_chart() const;
  [[nodiscard]] QChart* cohort_chart() const;
  [[nodiscard]] QLabel* session_header() const { return header_; }
  /// Rows the session table shows (after search and filter).
  [[nodiscard]] int visible_sessions() const;

 signals:
  /// The selected session's replay ended (ok: its plots and 3D replay are shown).
  void replay_finished(bool ok);
  /// The selected session's recorded frames are shown in the 3D replay, before its replay ends
  /// (a recording with frames: LAPREC05); `duration_s` the last frame's time.
  void recorded_frames_shown(double duration_s);

 private:
  void build_menus();
  QWidget* build_sessions_page();
  QWidget* build_curves_page();
  QWidget* build_cohort_page();
  void fill_trainees(const std::vector<QString>& names);
  void fill_sessions();
  void session_selected();
  void show_stored_metrics();
  void show_replay_metrics();
  void start_replay(const SessionRow& row);
  void stop_replay();
  void replay_done(uint64_t generation, std::shared_ptr<Result<sim::ReplayTimeline>> result);
  void frames_ready(uint64_t generation, std::shared_ptr<const sim::ReplayTimeline> frames);
  void refresh_curves();
  void refresh_cohort();
  void fill_curve_choices();
  void update_access();
  void ask_sign_in();
  void export_with_dialog(const QString& what, const QString& filter,
                          Status (ReviewWindow::*exporter)(const QString&));
  [[nodiscard]] const SessionRow* selected_row() const;
  [[nodiscard]] std::optional<sim::ProficiencySpec> proficiency_for(const QString& scenario_file);
  [[nodiscard]] QString current_trainee() const;
  void status(const QString& text);

  std::unique_ptr<SessionStore> owned_store_;  ///< when the window keeps its store
  SessionStore* store_;
  Viewer base_viewer_;
  Viewer viewer_;

  QLabel* who_ = nullptr;
  QListWidget* trainees_ = nullptr;
  QLineEdit* search_ = nullptr;
  QComboBox* result_filter_ = nullptr;
  QStandardItemModel* model_ = nullptr;
  QSortFilterProxyModel* proxy_ = nullptr;
  QTableView* table_ = nullptr;
  QLabel* header_ = nullptr;
  QTableWidget* metrics_ = nullptr;
  SessionCharts* charts_ = nullptr;
  ReplayPlayer* player_ = nullptr;
  QTabWidget* tabs_ = nullptr;
  QComboBox* curve_trainee_ = nullptr;
  QComboBox* curve_scenario_ = nullptr;
  QComboBox* curve_metric_ = nullptr;
  QChartView* curve_view_ = nullptr;
  QLabel* curve_verdict_ = nullptr;
  QComboBox* cohort_scenario_ = nullptr;
  QComboBox* cohort_metric_ = nullptr;
  QChartView* cohort_view_ = nullptr;
  QTableWidget* cohort_table_ = nullptr;
  QLabel* cohort_notice_ = nullptr;

  std::vector<SessionRow> rows_;  ///< the listed sessions (the model's rows, by index)
  QString selected_uuid_;
  std::map<QString, std::optional<sim::ProficiencySpec>> proficiency_cache_;

  // The replay of the selected session, on a worker thread.
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  uint64_t generation_ = 0;
  bool replay_done_ = false;
  bool frames_shown_ = false;  ///< the recorded frames are in the player, the replay still runs
  QString replay_status_;
  std::shared_ptr<const sim::ReplayTimeline> timeline_;
};

}  // namespace lap::app
