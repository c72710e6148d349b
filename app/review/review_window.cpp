#include "app/review/review_window.h"

#include <QAction>
#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QPainter>
#include <QSortFilterProxyModel>
#include <QSplitter>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableView>
#include <QTableWidget>
#include <QToolBar>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <new>
#include <set>

#include "app/review/progress_charts.h"
#include "app/review/replay_player.h"
#include "app/review/review_export.h"
#include "app/review/session_charts.h"
#include "sim/report/proficiency.h"
#include "sim/report/proficiency_progress.h"

namespace lap::app {

namespace {

enum Column {
  kStarted,
  kTrainee,
  kScenario,
  kResult,
  kReasons,
  kCompletion,
  kDuration,
  kStation,
  kColumns
};

// The session table's filter: the search text in any column, and the result.
class SessionTableFilter : public QSortFilterProxyModel {
 public:
  using QSortFilterProxyModel::QSortFilterProxyModel;
  void set_result(const QString& result) {
    result_ = result;
    invalidateFilter();
  }

 protected:
  bool filterAcceptsRow(int row, const QModelIndex& parent) const override {
    if (!result_.isEmpty()) {
      const QModelIndex i = sourceModel()->index(row, kResult, parent);
      if (!sourceModel()->data(i).toString().startsWith(result_)) return false;
    }
    return QSortFilterProxyModel::filterAcceptsRow(row, parent);
  }

 private:
  QString result_;
};

QStandardItem* item(const QString& text, const QVariant& sort_key) {
  auto* i = new QStandardItem(text);
  i->setData(sort_key, Qt::UserRole);
  i->setEditable(false);
  return i;
}

QString seconds(double v) { return std::isfinite(v) ? QString::number(v, 'f', 2) : QString("-"); }

QString value_text(double v) {
  return std::isfinite(v) ? QString::number(v, 'g', 5) : QStringLiteral("—");  // undefined
}

QString q(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

ReviewWindow::ReviewWindow(SessionStore* store, Viewer viewer, QWidget* parent)
    : QMainWindow(parent), store_(store), base_viewer_(viewer), viewer_(std::move(viewer)) {
  setWindowTitle(tr("laptrainer - review"));
  setObjectName(QStringLiteral("ReviewWindow"));
  resize(1400, 900);
  build_menus();
  tabs_ = new QTabWidget(this);
  tabs_->addTab(build_sessions_page(), tr("Sessions"));
  tabs_->addTab(build_curves_page(), tr("Learning curves"));
  tabs_->addTab(build_cohort_page(), tr("Cohort"));
  setCentralWidget(tabs_);
  connect(tabs_, &QTabWidget::currentChanged, this, [this](int i) {
    if (i == 1) refresh_curves();
    if (i == 2) refresh_cohort();
  });
  (void)reload();
}

ReviewWindow::ReviewWindow(std::unique_ptr<SessionStore> store, Viewer viewer, QWidget* parent)
    : ReviewWindow(store.get(), std::move(viewer), parent) {
  owned_store_ = std::move(store);
}

Result<ReviewWindow*> ReviewWindow::open_default(const QString& trainee) {
  Result<std::unique_ptr<SessionStore>> store = SessionStore::open_default();
  if (!store.ok()) return std::move(store).diagnostics();
  auto* window = new ReviewWindow(std::move(store).value(), Viewer::trainee(trainee));
  window->setAttribute(Qt::WA_DeleteOnClose);
  return window;
}

ReviewWindow::~ReviewWindow() { stop_replay(); }

// --- Building --------------------------------------------------------------------------------

void ReviewWindow::build_menus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  const auto add = [&](const QString& text, const QString& what, const QString& filter,
                       Status (ReviewWindow::*exporter)(const QString&)) {
    QAction* a = file->addAction(text);
    connect(a, &QAction::triggered, this,
            [this, what, filter, exporter] { export_with_dialog(what, filter, exporter); });
  };
  add(tr("Export session metrics (CSV)…"), tr("session metrics"), tr("CSV (*.csv)"),
      &ReviewWindow::export_session_metrics_csv);
  add(tr("Export raw series (CSV)…"), tr("raw series"), tr("CSV (*.csv)"),
      &ReviewWindow::export_series_csv);
  add(tr("Export session (JSON)…"), tr("session"), tr("JSON (*.json)"),
      &ReviewWindow::export_session_json);
  add(tr("Export session report (PDF)…"), tr("session report"), tr("PDF (*.pdf)"),
      &ReviewWindow::export_session_pdf);
  file->addSeparator();
  add(tr("Export trainee metrics (CSV)…"), tr("trainee metrics"), tr("CSV (*.csv)"),
      &ReviewWindow::export_trainee_csv);
  add(tr("Export trainee report (PDF)…"), tr("trainee report"), tr("PDF (*.pdf)"),
      &ReviewWindow::export_trainee_pdf);
  file->addSeparator();
  QAction* reload_action = file->addAction(tr("Reload"));
  reload_action->setShortcut(QKeySequence::Refresh);
  connect(reload_action, &QAction::triggered, this, [this] { (void)reload(); });
  QAction* close_action = file->addAction(tr("Close"));
  close_action->setShortcut(QKeySequence::Close);
  connect(close_action, &QAction::triggered, this, [this] { close(); });

  QToolBar* bar = addToolBar(tr("Who"));
  bar->setMovable(false);
  who_ = new QLabel(this);
  bar->addWidget(who_);
  bar->addSeparator();
  QAction* sign_in_action = bar->addAction(tr("Sign in as instructor…"));
  connect(sign_in_action, &QAction::triggered, this, [this] { ask_sign_in(); });
  QAction* sign_out_action = bar->addAction(tr("Sign out"));
  connect(sign_out_action, &QAction::triggered, this, [this] { sign_out(); });
}

QWidget* ReviewWindow::build_sessions_page() {
  auto* page = new QSplitter(Qt::Horizontal, this);
  auto* left = new QWidget(page);
  auto* left_layout = new QVBoxLayout(left);
  left_layout->setContentsMargins(0, 0, 0, 0);
  left_layout->addWidget(new QLabel(tr("Trainees"), left));
  trainees_ = new QListWidget(left);
  trainees_->setObjectName(QStringLiteral("trainees"));
  left_layout->addWidget(trainees_);
  connect(trainees_, &QListWidget::currentRowChanged, this, [this] { fill_sessions(); });

  auto* right = new QSplitter(Qt::Vertical, page);
  auto* list = new QWidget(right);
  auto* list_layout = new QVBoxLayout(list);
  list_layout->setContentsMargins(0, 0, 0, 0);
  auto* filters = new QHBoxLayout();
  search_ = new QLineEdit(list);
  search_->setObjectName(QStringLiteral("search"));
  search_->setPlaceholderText(tr("Search trainee, scenario, reasons, station, date…"));
  search_->setClearButtonEnabled(true);
  result_filter_ = new QComboBox(list);
  result_filter_->setObjectName(QStringLiteral("result"));
  result_filter_->addItem(tr("every result"), QString());
  for (const char* r : {"success", "failure", "incomplete"}) {
    result_filter_->addItem(QString::fromLatin1(r), QString::fromLatin1(r));
  }
  filters->addWidget(search_, 1);
  filters->addWidget(result_filter_);
  list_layout->addLayout(filters);
  model_ = new QStandardItemModel(0, kColumns, this);
  model_->setHorizontalHeaderLabels({tr("Started"), tr("Trainee"), tr("Scenario"), tr("Result"),
                                     tr("Reasons"), tr("Completion [s]"), tr("Duration [s]"),
                                     tr("Station")});
  auto* filter = new SessionTableFilter(this);
  proxy_ = filter;
  proxy_->setSourceModel(model_);
  proxy_->setSortRole(Qt::UserRole);
  proxy_->setFilterKeyColumn(-1);
  proxy_->setFilterCaseSensitivity(Qt::CaseInsensitive);
  table_ = new QTableView(list);
  table_->setObjectName(QStringLiteral("sessions"));
  table_->setModel(proxy_);
  table_->setSortingEnabled(true);
  table_->sortByColumn(kStarted, Qt::DescendingOrder);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->verticalHeader()->setVisible(false);
  list_layout->addWidget(table_);
  connect(search_, &QLineEdit::textChanged, this,
          [this](const QString& text) { proxy_->setFilterFixedString(text); });
  connect(result_filter_, &QComboBox::currentIndexChanged, this,
          [this, filter](int i) { filter->set_result(result_filter_->itemData(i).toString()); });
  connect(table_->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this] { session_selected(); });

  auto* detail = new QWidget(right);
  auto* detail_layout = new QVBoxLayout(detail);
  detail_layout->setContentsMargins(0, 0, 0, 0);
  header_ = new QLabel(tr("Select a session."), detail);
  header_->setObjectName(QStringLiteral("header"));
  header_->setWordWrap(true);
  header_->setTextFormat(Qt::RichText);
  detail_layout->addWidget(header_);
  auto* views = new QSplitter(Qt::Horizontal, detail);
  player_ = new ReplayPlayer(views);
  charts_ = new SessionCharts(views);
  metrics_ = new QTableWidget(0, 5, views);
  metrics_->setObjectName(QStringLiteral("metrics"));
  metrics_->setHorizontalHeaderLabels(
      {tr("metric"), tr("verdict"), tr("limit"), tr("stored"), tr("replayed")});
  metrics_->horizontalHeader()->setStretchLastSection(true);
  metrics_->verticalHeader()->setVisible(false);
  metrics_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  views->addWidget(player_);
  views->addWidget(charts_);
  views->addWidget(metrics_);
  views->setSizes({380, 520, 440});
  detail_layout->addWidget(views, 1);
  connect(player_, &ReplayPlayer::time_changed, charts_, &SessionCharts::set_cursor);
  right->addWidget(list);
  right->addWidget(detail);
  right->setSizes({260, 640});
  page->addWidget(left);
  page->addWidget(right);
  page->setSizes({180, 1220});
  return page;
}

QWidget* ReviewWindow::build_curves_page() {
  auto* page = new QWidget(this);
  auto* layout = new QVBoxLayout(page);
  auto* choices = new QHBoxLayout();
  curve_trainee_ = new QComboBox(page);
  curve_scenario_ = new QComboBox(page);
  curve_metric_ = new QComboBox(page);
  curve_metric_->setObjectName(QStringLiteral("curve_metric"));
  choices->addWidget(new QLabel(tr("Trainee"), page));
  choices->addWidget(curve_trainee_, 1);
  choices->addWidget(new QLabel(tr("Scenario"), page));
  choices->addWidget(curve_scenario_, 2);
  choices->addWidget(new QLabel(tr("Metric"), page));
  choices->addWidget(curve_metric_, 2);
  layout->addLayout(choices);
  curve_verdict_ = new QLabel(page);
  layout->addWidget(curve_verdict_);
  curve_view_ = new QChartView(new QChart(), page);
  curve_view_->setRenderHint(QPainter::Antialiasing);
  layout->addWidget(curve_view_, 1);
  connect(curve_trainee_, &QComboBox::currentIndexChanged, this, [this] { fill_curve_choices(); });
  connect(curve_scenario_, &QComboBox::currentIndexChanged, this, [this] { refresh_curves(); });
  connect(curve_metric_, &QComboBox::currentIndexChanged, this, [this] { refresh_curves(); });
  return page;
}

QWidget* ReviewWindow::build_cohort_page() {
  auto* page = new QWidget(this);
  auto* layout = new QVBoxLayout(page);
  cohort_notice_ = new QLabel(page);
  layout->addWidget(cohort_notice_);
  auto* choices = new QHBoxLayout();
  cohort_scenario_ = new QComboBox(page);
  cohort_metric_ = new QComboBox(page);
  cohort_metric_->setObjectName(QStringLiteral("cohort_metric"));
  choices->addWidget(new QLabel(tr("Scenario"), page));
  choices->addWidget(cohort_scenario_, 2);
  choices->addWidget(new QLabel(tr("Metric"), page));
  choices->addWidget(cohort_metric_, 2);
  layout->addLayout(choices);
  auto* split = new QSplitter(Qt::Vertical, page);
  cohort_view_ = new QChartView(new QChart(), split);
  cohort_view_->setRenderHint(QPainter::Antialiasing);
  cohort_table_ = new QTableWidget(0, 6, split);
  cohort_table_->setHorizontalHeaderLabels(
      {tr("trainee"), tr("sessions"), tr("successes"), tr("latest"), tr("best"), tr("proficient")});
  cohort_table_->horizontalHeader()->setStretchLastSection(true);
  cohort_table_->verticalHeader()->setVisible(false);
  cohort_table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  cohort_table_->setSortingEnabled(true);
  split->addWidget(cohort_view_);
  split->addWidget(cohort_table_);
  split->setStretchFactor(0, 3);  // the curves first: the table needs a row per trainee
  split->setStretchFactor(1, 1);
  split->setSizes({560, 200});
  layout->addWidget(split, 1);
  connect(cohort_scenario_, &QComboBox::currentIndexChanged, this, [this] { refresh_cohort(); });
  connect(cohort_metric_, &QComboBox::currentIndexChanged, this, [this] { refresh_cohort(); });
  return page;
}

QChart* ReviewWindow::learning_chart() const { return curve_view_->chart(); }
QChart* ReviewWindow::cohort_chart() const { return cohort_view_->chart(); }

void ReviewWindow::status(const QString& text) { statusBar()->showMessage(text); }

// --- Who may see what ------------------------------------------------------------------------

void ReviewWindow::update_access() {
  who_->setText(
      viewer_.is_instructor()    ? tr("Instructor %1: every trainee's sessions").arg(viewer_.name())
      : viewer_.name().isEmpty() ? tr("Nobody signed in: sign in as an instructor")
                                 : tr("Trainee %1: your own sessions").arg(viewer_.name()));
  tabs_->setTabEnabled(2, viewer_.is_instructor());
  cohort_notice_->setText(viewer_.is_instructor()
                              ? tr("Every trainee's learning curve for one metric, against the "
                                   "experts' band.")
                              : tr("The cohort is for instructors: sign in."));
}

Status ReviewWindow::sign_in(const QString& name, const QString& password) {
  Result<Viewer> signed_in = store_->sign_in_instructor(name, password);
  if (!signed_in.ok()) {
    status(q(signed_in.message()));
    return std::move(signed_in).diagnostics();
  }
  viewer_ = signed_in.value();
  return reload();
}

void ReviewWindow::sign_out() {
  viewer_ = base_viewer_;
  (void)reload();
}

void ReviewWindow::ask_sign_in() {
  QDialog dialog(this);
  dialog.setWindowTitle(tr("Sign in as instructor"));
  auto* form = new QFormLayout(&dialog);
  auto* name = new QLineEdit(&dialog);
  auto* password = new QLineEdit(&dialog);
  password->setEchoMode(QLineEdit::Password);
  form->addRow(tr("Name"), name);
  form->addRow(tr("Password"), password);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, &dialog);
  form->addRow(buttons);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  if (dialog.exec() != QDialog::Accepted) return;
  const Status signed_in = sign_in(name->text(), password->text());
  if (!signed_in.ok()) {
    QMessageBox::warning(this, tr("Sign in"), q(signed_in.message()));
  }
}

// --- Trainees and sessions -------------------------------------------------------------------

Status ReviewWindow::reload() {
  update_access();
  Result<std::vector<QString>> names = store_->trainees(viewer_);
  if (!names.ok()) {
    status(q(names.message()));
    fill_trainees({});
    return std::move(names).diagnostics();
  }
  fill_trainees(names.value());
  const SyncStatus sync = store_->sync_status();
  if (sync.server_configured && !sync.server_reachable) {
    status(tr("The programme's server does not answer: this station's sessions only (%1)")
               .arg(sync.last_error));
  }
  return {};
}

void ReviewWindow::fill_trainees(const std::vector<QString>& names) {
  const QString keep = current_trainee();
  trainees_->blockSignals(true);
  trainees_->clear();
  if (viewer_.is_instructor()) {
    auto* all = new QListWidgetItem(tr("All trainees"), trainees_);
    all->setData(Qt::UserRole, QString());
  }
  for (const QString& n : names) {
    auto* i = new QListWidgetItem(n, trainees_);
    i->setData(Qt::UserRole, n);
  }
  int row = 0;
  for (int i = 0; i < trainees_->count(); ++i) {
    if (trainees_->item(i)->data(Qt::UserRole).toString() == keep) row = i;
  }
  trainees_->setCurrentRow(trainees_->count() > 0 ? row : -1);
  trainees_->blockSignals(false);
  curve_trainee_->blockSignals(true);
  curve_trainee_->clear();
  for (const QString& n : names) curve_trainee_->addItem(n, n);
  curve_trainee_->blockSignals(false);
  fill_sessions();
  fill_curve_choices();
}

QString ReviewWindow::current_trainee() const {
  const QListWidgetItem* i = trainees_ != nullptr ? trainees_->currentItem() : nullptr;
  return i != nullptr ? i->data(Qt::UserRole).toString() : QString();
}

void ReviewWindow::select_trainee(const QString& name) {
  for (int i = 0; i < trainees_->count(); ++i) {
    if (trainees_->item(i)->data(Qt::UserRole).toString() == name) {
      trainees_->setCurrentRow(i);
      return;
    }
  }
}

void ReviewWindow::fill_sessions() {
  const QString trainee = current_trainee();
  Result<std::vector<SessionRow>> rows =
      trainee.isEmpty() ? store_->all_sessions(viewer_) : store_->sessions(viewer_, trainee);
  model_->removeRows(0, model_->rowCount());
  rows_.clear();
  if (!rows.ok()) {
    status(q(rows.message()));
    return;
  }
  rows_ = std::move(rows).value();
  for (const SessionRow& r : rows_) {
    const QString result =
        r.result + (r.interrupted ? QStringLiteral(" (interrupted)") : QString());
    const QList<QStandardItem*> cells = {
        item(r.started_utc.toLocalTime().toString(QStringLiteral("yyyy-MM-dd HH:mm:ss")),
             utc_text(r.started_utc)),
        item(r.trainee, r.trainee),
        item(r.scenario_name.isEmpty() ? r.scenario_file : r.scenario_name, r.scenario_file),
        item(result, result),
        item(r.reasons.join(QStringLiteral(", ")), r.reasons.join(QStringLiteral(", "))),
        item(seconds(r.completion_time_s),
             std::isfinite(r.completion_time_s) ? r.completion_time_s : 1e300),
        item(seconds(r.duration_s), r.duration_s),
        item(r.station, r.station)};
    cells[kStarted]->setData(r.uuid, Qt::UserRole + 1);
    cells[kStarted]->setToolTip(r.uuid + QStringLiteral("\n") + r.recording_dir);
    model_->appendRow(cells);
  }
  table_->resizeColumnsToContents();
  status(tr("%n session(s)", "", static_cast<int>(rows_.size())));
  if (!selected_uuid_.isEmpty()) (void)select_session(selected_uuid_);
}

int ReviewWindow::visible_sessions() const { return proxy_->rowCount(); }

bool ReviewWindow::select_session(const QString& uuid) {
  for (int r = 0; r < proxy_->rowCount(); ++r) {
    const QModelIndex i = proxy_->index(r, kStarted);
    if (proxy_->data(i, Qt::UserRole + 1).toString() == uuid) {
      table_->setCurrentIndex(i);
      table_->selectRow(r);
      if (selected_uuid_ != uuid) session_selected();
      return true;
    }
  }
  return false;
}

const SessionRow* ReviewWindow::selected_row() const {
  for (const SessionRow& r : rows_) {
    if (r.uuid == selected_uuid_) return &r;
  }
  return nullptr;
}

std::optional<sim::ProficiencySpec> ReviewWindow::proficiency_for(const QString& scenario_file) {
  const auto it = proficiency_cache_.find(scenario_file);
  if (it != proficiency_cache_.end()) return it->second;
  std::optional<sim::ProficiencySpec> spec = scenario_proficiency(scenario_file);
  proficiency_cache_[scenario_file] = spec;
  return spec;
}

void ReviewWindow::session_selected() {
  const QModelIndex current = table_->currentIndex();
  if (!current.isValid()) return;
  const QString uuid =
      proxy_->data(proxy_->index(current.row(), kStarted), Qt::UserRole + 1).toString();
  if (uuid == selected_uuid_ && (timeline_ || worker_.joinable())) return;
  selected_uuid_ = uuid;
  const SessionRow* row = selected_row();
  if (row == nullptr) return;
  QString text =
      QStringLiteral("<b>%1</b> — %2 — %3<br>")
          .arg(row->trainee.toHtmlEscaped(),
               row->started_utc.toLocalTime().toString(QStringLiteral("yyyy-MM-dd HH:mm")),
               (row->scenario_name.isEmpty() ? row->scenario_file : row->scenario_name)
                   .toHtmlEscaped());
  const QString color = row->result == QLatin1String("success")   ? QStringLiteral("#0a8c33")
                        : row->result == QLatin1String("failure") ? QStringLiteral("#cc1a1a")
                                                                  : QStringLiteral("#333333");
  text += QStringLiteral("<span style='color:%1; font-size:14pt'><b>%2</b></span>")
              .arg(color, row->result + (row->reasons.isEmpty()
                                             ? QString()
                                             : QStringLiteral(": ") +
                                                   row->reasons.join(QStringLiteral(", "))));
  if (std::isfinite(row->completion_time_s)) {
    text += tr(" at %1 s").arg(row->completion_time_s, 0, 'f', 2);
  }
  if (row->interrupted) text += tr(" — <i>interrupted (the recording has no end)</i>");
  text += QStringLiteral("<br><small>%1 · %2</small>")
              .arg(row->devices.toHtmlEscaped(), row->station.toHtmlEscaped());
  header_->setText(text);
  show_stored_metrics();
  start_replay(*row);
}

void ReviewWindow::show_stored_metrics() {
  metrics_->setRowCount(0);
  const SessionRow* row = selected_row();
  if (row == nullptr) return;
  Result<std::vector<MetricValue>> stored = store_->metrics(viewer_, row->uuid);
  if (!stored.ok()) {
    status(q(stored.message()));
    return;
  }
  std::vector<sim::Metric> metrics = to_metrics(stored.value());
  std::vector<sim::BenchmarkResult> verdicts;
  if (const std::optional<sim::ProficiencySpec> spec = proficiency_for(row->scenario_file)) {
    verdicts = sim::assess_proficiency(*spec, metrics);
  }
  // The metrics the trainee is judged on first, the rest (descriptive) after, each in order.
  std::stable_partition(metrics.begin(), metrics.end(), [&](const sim::Metric& m) {
    return std::any_of(verdicts.begin(), verdicts.end(),
                       [&](const sim::BenchmarkResult& r) { return r.benchmark.metric == m.name; });
  });
  metrics_->setRowCount(static_cast<int>(metrics.size()));
  for (int i = 0; i < static_cast<int>(metrics.size()); ++i) {
    const sim::Metric& m = metrics[static_cast<size_t>(i)];
    metrics_->setItem(i, kMetricName, new QTableWidgetItem(q(m.name)));
    metrics_->setItem(i, kMetricStored, new QTableWidgetItem(value_text(m.value)));
    metrics_->setItem(i, kMetricReplayed, new QTableWidgetItem(tr("replaying…")));
    for (const sim::BenchmarkResult& r : verdicts) {
      if (r.benchmark.metric != m.name) continue;
      metrics_->setItem(i, kMetricLimit,
                        new QTableWidgetItem((r.benchmark.higher_is_better ? "≥ " : "≤ ") +
                                             QString::number(r.limit, 'g', 4)));
      auto* verdict = new QTableWidgetItem(r.met ? tr("pass") : tr("FAIL"));
      verdict->setForeground(r.met ? QColor(13, 140, 51) : QColor(204, 26, 26));
      metrics_->setItem(i, kMetricVerdict, verdict);
    }
  }
  metrics_->resizeColumnsToContents();
}

void ReviewWindow::show_replay_metrics() {
  if (!timeline_) return;
  const std::vector<sim::Metric>& replayed = timeline_->session().metrics.training;
  for (int i = 0; i < metrics_->rowCount(); ++i) {
    const QString name = metrics_->item(i, kMetricName)->text();
    QString text = tr("-");
    for (const sim::Metric& m : replayed) {
      if (q(m.name) == name) text = value_text(m.value);
    }
    metrics_->setItem(i, kMetricReplayed, new QTableWidgetItem(text));
  }
  metrics_->resizeColumnsToContents();
}

// --- The replay ------------------------------------------------------------------------------

void ReviewWindow::stop_replay() {
  cancel_.store(true);
  if (worker_.joinable()) worker_.join();
  cancel_.store(false);
}

void ReviewWindow::start_replay(const SessionRow& row) {
  stop_replay();
  const uint64_t generation = ++generation_;
  timeline_.reset();
  replay_done_ = false;
  frames_shown_ = false;
  player_->set_timeline(nullptr);
  charts_->clear(tr("replaying the recording…"));
  if (row.recording_dir.isEmpty()) {
    replay_done_ = true;
    replay_status_ = tr("this session has no recording: its metrics only");
    charts_->clear(tr("no recording"));
    status(replay_status_);
    emit replay_finished(false);
    return;
  }
  replay_status_ = tr("replaying %1…").arg(row.recording_dir);
  status(replay_status_);
  const std::filesystem::path dir = row.recording_dir.toStdString();
  worker_ = std::thread([this, dir, generation] {
    // The frames the recording kept (LAPREC05) first: the 3D replay can be scrubbed at once,
    // while the replay below recomputes the metrics and plots (a 10-minute session's takes
    // tens of seconds). Without frames the replay's own are shown when it ends.
    Result<sim::ReplayTimeline> recorded = diagnostic("no frames");
    try {
      recorded = sim::ReplayTimeline::from_recorded_frames(dir);
    } catch (const std::bad_alloc&) {
      recorded = diagnostic("the recording's frames do not fit in memory");  // the replay follows
    }
    if (recorded.ok() && !cancel_.load()) {
      auto frames = std::make_shared<const sim::ReplayTimeline>(std::move(recorded).value());
      QMetaObject::invokeMethod(
          this, [this, generation, frames] { frames_ready(generation, frames); },
          Qt::QueuedConnection);
    }
    int last_percent = -1;
    auto result = std::make_shared<Result<sim::ReplayTimeline>>(sim::ReplayTimeline::replay(
        dir, sim::ReplayTimeline::kDefaultFramePeriodS, [&](double fraction) {
          const int percent = static_cast<int>(fraction * 100.0);
          if (percent != last_percent) {
            last_percent = percent;
            QMetaObject::invokeMethod(
                this,
                [this, percent, generation] {
                  if (generation == generation_) {
                    status(frames_shown_ ? tr("showing the recorded frames; replaying the "
                                              "recording for the metrics and plots: %1 %")
                                               .arg(percent)
                                         : tr("replaying the recording: %1 %").arg(percent));
                  }
                },
                Qt::QueuedConnection);
          }
          return !cancel_.load();
        }));
    QMetaObject::invokeMethod(
        this, [this, generation, result] { replay_done(generation, result); },
        Qt::QueuedConnection);
  });
}

void ReviewWindow::frames_ready(uint64_t generation,
                                std::shared_ptr<const sim::ReplayTimeline> frames) {
  if (generation != generation_ || replay_done_) return;
  player_->set_timeline(frames);
  frames_shown_ = true;
  status(tr("showing the recorded frames (%1 s); replaying the recording for the metrics and "
            "plots…")
             .arg(frames->duration_s(), 0, 'f', 1));
  emit recorded_frames_shown(frames->duration_s());
}

void ReviewWindow::replay_done(uint64_t generation,
                               std::shared_ptr<Result<sim::ReplayTimeline>> result) {
  if (generation != generation_) return;  // a session selected since
  if (worker_.joinable()) worker_.join();
  replay_done_ = true;
  if (!result->ok()) {
    frames_shown_ = false;  // the recorded frames, if any, stay in the 3D replay
    replay_status_ = tr("cannot replay the recording: %1").arg(q(result->message()));
    charts_->clear(tr("no replay"));
    status(replay_status_);
    emit replay_finished(false);
    return;
  }
  timeline_ = std::make_shared<const sim::ReplayTimeline>(std::move(*result).value());
  const sim::ReplayedSession& r = timeline_->session();
  double injury = 0.0, depth = 0.0;
  if (r.task) {
    injury = r.task->duct_injury_force_n;
    depth = r.task->insertion_depth_m;
  }
  charts_->set_session(r.metrics.series, r.metrics.task, injury, depth);
  // Where the reviewer was in the recorded frames, in the replay's (20 a second).
  const double at_s = frames_shown_ ? player_->time_s() : 0.0;
  const bool playing = frames_shown_ && player_->playing();
  frames_shown_ = false;
  player_->set_timeline(timeline_);
  if (at_s > 0.0) player_->seek(at_s);
  if (playing) player_->play();
  show_replay_metrics();
  QStringList notes;
  for (const std::string& n : r.notes) notes << q(n);
  for (const std::string& p : r.recording_problems) notes << q(p);
  replay_status_ = tr("replayed: %1 frames over %2 s")
                       .arg(timeline_->size())
                       .arg(timeline_->duration_s(), 0, 'f', 2) +
                   (notes.isEmpty() ? QString() : QStringLiteral(" — ") + notes.join("; "));
  status(replay_status_);
  emit replay_finished(true);
}

QString ReviewWindow::replay_status() const { return replay_status_; }

// --- Learning curves and cohort --------------------------------------------------------------

void ReviewWindow::fill_curve_choices() {
  const QString trainee = curve_trainee_->currentData().toString();
  curve_scenario_->blockSignals(true);
  curve_metric_->blockSignals(true);
  curve_scenario_->clear();
  curve_metric_->clear();
  cohort_scenario_->blockSignals(true);
  cohort_metric_->blockSignals(true);
  cohort_scenario_->clear();
  cohort_metric_->clear();
  std::set<QString> scenarios, cohort_scenarios;
  std::vector<QString> metric_names;
  if (!trainee.isEmpty()) {
    Result<std::vector<SessionRow>> rows = store_->sessions(viewer_, trainee);
    if (rows.ok()) {
      for (const SessionRow& r : rows.value()) scenarios.insert(r.scenario_file);
      if (!rows->empty()) {
        Result<std::vector<MetricValue>> m = store_->metrics(viewer_, rows->front().uuid);
        if (m.ok()) {
          for (const MetricValue& v : m.value()) metric_names.push_back(v.name);
        }
      }
    }
  }
  if (viewer_.is_instructor()) {
    Result<std::vector<SessionRow>> all = store_->all_sessions(viewer_);
    if (all.ok()) {
      for (const SessionRow& r : all.value()) cohort_scenarios.insert(r.scenario_file);
      if (metric_names.empty() && !all->empty()) {
        Result<std::vector<MetricValue>> m = store_->metrics(viewer_, all->front().uuid);
        if (m.ok()) {
          for (const MetricValue& v : m.value()) metric_names.push_back(v.name);
        }
      }
    }
  }
  // Benchmarked metrics first: those are the ones a trainee is judged on.
  std::set<QString> benchmarked;
  for (const std::set<QString>* set : {&scenarios, &cohort_scenarios}) {
    for (const QString& s : *set) {
      if (const auto spec = proficiency_for(s)) {
        for (const sim::MetricBenchmark& b : spec->metrics) benchmarked.insert(q(b.metric));
      }
    }
  }
  std::stable_partition(metric_names.begin(), metric_names.end(),
                        [&](const QString& n) { return benchmarked.count(n) != 0; });
  for (const QString& s : scenarios) curve_scenario_->addItem(s, s);
  for (const QString& s : cohort_scenarios) cohort_scenario_->addItem(s, s);
  for (const QString& n : metric_names) {
    const QString label = benchmarked.count(n) != 0 ? n + QStringLiteral("  ★") : n;
    curve_metric_->addItem(label, n);
    cohort_metric_->addItem(label, n);
  }
  curve_scenario_->blockSignals(false);
  curve_metric_->blockSignals(false);
  cohort_scenario_->blockSignals(false);
  cohort_metric_->blockSignals(false);
  if (tabs_ != nullptr && tabs_->currentIndex() == 1) refresh_curves();
  if (tabs_ != nullptr && tabs_->currentIndex() == 2) refresh_cohort();
}

namespace {

std::optional<sim::MetricBenchmark> benchmark_of(const std::optional<sim::ProficiencySpec>& spec,
                                                 const QString& metric) {
  if (!spec) return std::nullopt;
  for (const sim::MetricBenchmark& b : spec->metrics) {
    if (q(b.metric) == metric) return b;
  }
  return std::nullopt;
}

}  // namespace

void ReviewWindow::refresh_curves() {
  const QString trainee = curve_trainee_->currentData().toString();
  const QString scenario = curve_scenario_->currentData().toString();
  const QString metric = curve_metric_->currentData().toString();
  if (trainee.isEmpty() || metric.isEmpty()) {
    learning_chart()->removeAllSeries();
    curve_verdict_->setText(tr("No sessions to draw."));
    return;
  }
  Result<std::vector<MetricPoint>> points =
      store_->metric_history(viewer_, metric, trainee, scenario);
  if (!points.ok()) {
    curve_verdict_->setText(q(points.message()));
    return;
  }
  const std::optional<sim::MetricBenchmark> benchmark =
      benchmark_of(proficiency_for(scenario), metric);
  draw_learning_curve(learning_chart(), tr("%1 — %2").arg(trainee, metric), points.value(),
                      benchmark);
  if (!benchmark) {
    curve_verdict_->setText(tr("%1 has no expert benchmark in this scenario.").arg(metric));
    return;
  }
  sim::ProficiencySpec one;
  one.metrics = {*benchmark};
  std::vector<std::vector<sim::Metric>> sessions;
  for (const MetricPoint& p : points.value()) sessions.push_back({{metric.toStdString(), p.value}});
  const std::vector<sim::ProficiencyProgress> progress = sim::proficiency_progress(one, sessions);
  const int at = progress.empty() ? -1 : progress.front().proficient_at;
  curve_verdict_->setText(at >= 0 ? tr("Proficient in %1 from session %2 (met in two consecutive "
                                       "sessions).")
                                        .arg(metric)
                                        .arg(at + 1)
                                  : tr("Not yet proficient in %1 (needs the limit met in two "
                                       "consecutive sessions).")
                                        .arg(metric));
}

void ReviewWindow::refresh_cohort() {
  cohort_table_->setRowCount(0);
  if (!viewer_.is_instructor()) {
    cohort_chart()->removeAllSeries();
    return;
  }
  const QString scenario = cohort_scenario_->currentData().toString();
  const QString metric = cohort_metric_->currentData().toString();
  if (metric.isEmpty()) return;
  Result<std::vector<MetricPoint>> points =
      store_->metric_history(viewer_, metric, QString(), scenario);
  if (!points.ok()) {
    cohort_notice_->setText(q(points.message()));
    return;
  }
  const std::optional<sim::MetricBenchmark> benchmark =
      benchmark_of(proficiency_for(scenario), metric);
  draw_cohort(cohort_chart(), tr("Cohort — %1").arg(metric), points.value(), benchmark);
  // The table: per trainee, their sessions of this scenario.
  std::map<QString, std::vector<MetricPoint>> by_trainee;
  for (const MetricPoint& p : points.value()) by_trainee[p.trainee].push_back(p);
  Result<std::vector<SessionRow>> all = store_->all_sessions(viewer_);
  cohort_table_->setSortingEnabled(false);
  cohort_table_->setRowCount(static_cast<int>(by_trainee.size()));
  int row = 0;
  for (const auto& [trainee, list] : by_trainee) {
    int successes = 0, count = 0;
    if (all.ok()) {
      for (const SessionRow& r : all.value()) {
        if (r.trainee != trainee || (!scenario.isEmpty() && r.scenario_file != scenario)) continue;
        ++count;
        successes += r.result == QLatin1String("success") ? 1 : 0;
      }
    }
    double best = NAN;
    for (const MetricPoint& p : list) {
      if (!std::isfinite(p.value)) continue;
      const bool higher = benchmark && benchmark->higher_is_better;
      if (!std::isfinite(best) || (higher ? p.value > best : p.value < best)) best = p.value;
    }
    QString proficient = tr("no benchmark");
    if (benchmark) {
      sim::ProficiencySpec one;
      one.metrics = {*benchmark};
      std::vector<std::vector<sim::Metric>> sessions;
      for (const MetricPoint& p : list) sessions.push_back({{metric.toStdString(), p.value}});
      const int at = sim::proficiency_progress(one, sessions).front().proficient_at;
      proficient = at >= 0 ? tr("from session %1").arg(at + 1) : tr("not yet");
    }
    const auto cell = [&](int column, const QVariant& v) {
      auto* i = new QTableWidgetItem();
      i->setData(Qt::DisplayRole, v);
      cohort_table_->setItem(row, column, i);
    };
    cell(0, trainee);
    cell(1, count);
    cell(2, successes);
    cell(3, value_text(list.back().value));
    cell(4, value_text(best));
    cell(5, proficient);
    ++row;
  }
  cohort_table_->setSortingEnabled(true);
  cohort_table_->resizeColumnsToContents();
}

// --- Exports ---------------------------------------------------------------------------------

void ReviewWindow::export_with_dialog(const QString& what, const QString& filter,
                                      Status (ReviewWindow::*exporter)(const QString&)) {
  const QString file =
      QFileDialog::getSaveFileName(this, tr("Export %1").arg(what), QString(), filter);
  if (file.isEmpty()) return;
  const Status done = (this->*exporter)(file);
  if (!done.ok()) {
    QMessageBox::warning(this, tr("Export %1").arg(what), q(done.message()));
    return;
  }
  status(tr("%1 written to %2").arg(what, file));
}

namespace {

Diagnostic nothing_selected() { return diagnostic("export: select a session first"); }
Diagnostic not_replayed() {
  return diagnostic(
      "export: the session's replay is not ready (or its recording could not be "
      "replayed): wait for it, or export the stored metrics");
}

}  // namespace

Status ReviewWindow::export_session_metrics_csv(const QString& file) {
  const SessionRow* row = selected_row();
  if (row == nullptr) return nothing_selected();
  std::vector<sim::Metric> metrics;
  if (timeline_) {
    metrics = timeline_->session().metrics.training;
  } else {
    Result<std::vector<MetricValue>> stored = store_->metrics(viewer_, row->uuid);
    if (!stored.ok()) return std::move(stored).diagnostics();
    metrics = to_metrics(stored.value());
  }
  return write_export(file, metrics_csv(metrics, proficiency_for(row->scenario_file)));
}

Status ReviewWindow::export_series_csv(const QString& file) {
  if (selected_row() == nullptr) return nothing_selected();
  if (!timeline_) return not_replayed();
  return write_export(file, series_csv(timeline_->session().metrics.series));
}

Status ReviewWindow::export_session_json(const QString& file) {
  const SessionRow* row = selected_row();
  if (row == nullptr) return nothing_selected();
  return write_export(file, session_json(*row, timeline_ ? &timeline_->session() : nullptr));
}

Status ReviewWindow::export_session_pdf(const QString& file) {
  const SessionRow* row = selected_row();
  if (row == nullptr) return nothing_selected();
  if (!timeline_) return not_replayed();
  return write_export(file, session_pdf_bytes(*row, timeline_->session()));
}

namespace {

struct TraineeData {
  QString trainee;
  QString scenario_file;
  QString scenario_name;
  std::vector<SessionRow> sessions;  // oldest first
  std::vector<std::vector<MetricValue>> metrics;
};

}  // namespace

Status ReviewWindow::export_trainee_csv(const QString& file) {
  const SessionRow* row = selected_row();
  const QString trainee = !current_trainee().isEmpty() ? current_trainee()
                          : row != nullptr             ? row->trainee
                                                       : QString();
  if (trainee.isEmpty()) return diagnostic("export: select a trainee or one of their sessions");
  Result<std::vector<SessionRow>> rows = store_->sessions(viewer_, trainee);
  if (!rows.ok()) return std::move(rows).diagnostics();
  std::vector<SessionRow> sessions(rows->rbegin(), rows->rend());
  std::vector<std::vector<MetricValue>> metrics;
  std::vector<QString> names;
  for (const SessionRow& r : sessions) {
    Result<std::vector<MetricValue>> m = store_->metrics(viewer_, r.uuid);
    if (!m.ok()) return std::move(m).diagnostics();
    for (const MetricValue& v : m.value()) {
      if (std::find(names.begin(), names.end(), v.name) == names.end()) names.push_back(v.name);
    }
    metrics.push_back(std::move(m).value());
  }
  return write_export(file, trainee_metrics_csv(sessions, metrics, names));
}

Status ReviewWindow::export_trainee_pdf(const QString& file) {
  const SessionRow* row = selected_row();
  if (row == nullptr) {
    return diagnostic(
        "export: select one of the trainee's sessions (its scenario is the report's)");
  }
  const QString trainee = row->trainee;
  Result<std::vector<SessionRow>> rows = store_->sessions(viewer_, trainee, row->scenario_file);
  if (!rows.ok()) return std::move(rows).diagnostics();
  std::vector<SessionRow> sessions(rows->rbegin(), rows->rend());
  std::vector<std::vector<MetricValue>> metrics;
  for (const SessionRow& r : sessions) {
    Result<std::vector<MetricValue>> m = store_->metrics(viewer_, r.uuid);
    if (!m.ok()) return std::move(m).diagnostics();
    metrics.push_back(std::move(m).value());
  }
  std::string why;
  const std::optional<sim::ProficiencySpec> spec = scenario_proficiency(row->scenario_file, &why);
  sim::TraineePdfContext context =
      trainee_report(trainee, row->scenario_name, row->scenario_file, sessions, metrics, spec);
  if (!spec && !why.empty()) context.notes.push_back(why);
  return write_export(file, sim::trainee_pdf(context).bytes());
}

}  // namespace lap::app
