// The instructor's review window (app/review) driven as an instructor would, with Qt Test's
// synthetic mouse and key events, under a virtual X server: a real session recorded by
// `laptrainer-cli run --fast --record` (the introductory scenario's expert) is stored beside two
// older ones; the instructor signs in, picks the trainee and the session, sees its metrics with
// their verdicts and its plots once the recording is replayed, plays, scrubs and changes speed with
// the plots' cursor in step, reads the learning curve and the cohort, and exports the CSV, JSON
// and PDF files (the PDF rendered by pdftoppm). A trainee sees their own sessions only.
//
// LAP_REVIEW_SCREENSHOTS=DIR also writes the window and a PDF page as PNG there (the issue's
// screenshots).

#include "app/review/review_window.h"

#include <gtest/gtest.h>
#include <vtkAutoInit.h>

#include <QApplication>
#include <QChart>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QLineEdit>
#include <QListWidget>
#include <QProcess>
#include <QScreen>
#include <QSlider>
#include <QTabBar>
#include <QTabWidget>
#include <QTableView>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QTimeZone>
#include <QToolButton>
#include <QUuid>
#include <QXYSeries>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/review/replay_player.h"
#include "app/review/session_charts.h"
#include "app/store/session_store.h"

VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkInteractionStyle);

namespace lap::app {
namespace {

const QString kPassword = QStringLiteral("laparoscopy-2025");

bool wait_until(const std::function<bool()>& done, int timeout_ms) {
  QElapsedTimer clock;
  clock.start();
  while (!done()) {
    if (clock.elapsed() > timeout_ms) return false;
    QTest::qWait(20);
  }
  return true;
}

QString source(const char* relative) {
  return QStringLiteral(LAP_SOURCE_DIR) + QLatin1Char('/') + QLatin1String(relative);
}

QString read_text(const QString& file) {
  QFile f(file);
  return f.open(QIODevice::ReadOnly) ? QString::fromUtf8(f.readAll()) : QString();
}

// A session for the store: the given trainee and time; `report` the run JSON.
SessionRow session_row(const QString& trainee, const QDateTime& started, const QString& report,
                       const QString& recording, const QString& result) {
  SessionRow r;
  r.uuid = QUuid::createUuid().toString(QUuid::WithoutBraces);
  r.trainee = trainee;
  r.scenario_file = source("scenarios/introductory.yaml");
  r.scenario_name = QStringLiteral("Catheter insertion");
  r.scenario_version = file_sha256(r.scenario_file).value();
  r.devices = QStringLiteral("left=scripted; right=scripted");
  r.station = QStringLiteral("test-station");
  r.started_utc = started;
  r.duration_s = 17.0;
  r.result = result;
  r.completion_time_s = 16.0;
  r.report_json = report;
  r.recording_dir = recording;
  return r;
}

QString metrics_report(double completion_s, double max_force_n) {
  return QStringLiteral(R"({"metrics": {"completion_time_s": %1, "max_force_duct_n": %2,
                            "catheter_drops": 0}})")
      .arg(completion_s)
      .arg(max_force_n);
}

// The stored row of a recorded run: its result, reasons and completion time from its JSON.
SessionRow recorded_row(const QString& trainee, const QDateTime& started, const QString& report,
                        const QString& recording) {
  const nlohmann::json j = nlohmann::json::parse(report.toStdString());
  const nlohmann::json& task = j.at("task");
  SessionRow r = session_row(trainee, started, report, recording,
                             QString::fromStdString(task.at("result").get<std::string>()));
  for (const auto& reason : task.at("reasons")) {
    r.reasons << QString::fromStdString(reason.get<std::string>());
  }
  r.completion_time_s = task.at("completion_time_s").is_number()
                            ? task.at("completion_time_s").get<double>()
                            : std::numeric_limits<double>::quiet_NaN();
  r.duration_s = static_cast<double>(j.at("recorded_ticks").get<int64_t>()) * 1e-3;  // 1 kHz
  return r;
}

class ReviewWindowTest : public ::testing::Test {
 protected:
  // Runs the introductory scenario with one of its shipped scripts (expert, clumsy_overshoot, …),
  // recorded into `recording`; returns the run JSON.
  static QString record(const QString& script, const QString& recording) {
    QProcess run;
    run.setProgram(QStringLiteral(LAP_BIN_DIR "/laptrainer-cli"));
    const QString scripts = source("scenarios/scripts/introductory/");
    run.setArguments({QStringLiteral("run"), QStringLiteral("--scenario"),
                      source("scenarios/introductory.yaml"), QStringLiteral("--left"),
                      QStringLiteral("scripted:") + scripts + script + QStringLiteral("_left.csv"),
                      QStringLiteral("--right"),
                      QStringLiteral("scripted:") + scripts + script + QStringLiteral("_right.csv"),
                      QStringLiteral("--fast"), QStringLiteral("--duration"), QStringLiteral("60"),
                      QStringLiteral("--record"), recording});
    run.start();
    if (!run.waitForFinished(120000) || run.exitCode() != 0) {
      ADD_FAILURE() << script.toStdString() << ": " << run.readAllStandardError().toStdString();
      return {};
    }
    return QString::fromUtf8(run.readAllStandardOutput());
  }

  void SetUp() override {
    ASSERT_TRUE(dir_.isValid());
    // Real sessions: the introductory scenario's expert (about 16 s, a success) and the clumsy
    // trainee who pushes past the target (a failure), both recorded.
    recording_ = dir_.path() + QStringLiteral("/expert");
    report_ = record(QStringLiteral("expert"), recording_);
    ASSERT_FALSE(report_.isEmpty());
    const QString overshoot_dir = dir_.path() + QStringLiteral("/overshoot");
    const QString overshoot = record(QStringLiteral("clumsy_overshoot"), overshoot_dir);
    ASSERT_FALSE(overshoot.isEmpty());
    StoreConnection c;
    c.sqlite_path = dir_.path() + QStringLiteral("/sessions.sqlite");
    c.station = QStringLiteral("test-station");
    Result<std::unique_ptr<SessionStore>> store = SessionStore::open(c);
    ASSERT_TRUE(store.ok()) << store.message();
    store_ = std::move(store).value();
    ASSERT_TRUE(
        store_->set_instructor_password(nullptr, QStringLiteral("dr-lee"), kPassword, 1000).ok());
    const QDateTime now = QDateTime::currentDateTimeUtc();
    // ana: the overshoot two days ago, a session without a recording yesterday, the expert's
    // run now; ben: one session without a recording.
    ASSERT_TRUE(
        store_->add_session(recorded_row("ana", now.addDays(-2), overshoot, overshoot_dir)).ok());
    ASSERT_TRUE(store_
                    ->add_session(session_row("ana", now.addDays(-1), metrics_report(16.2, 0.41),
                                              {}, "success"))
                    .ok());
    recorded_ = recorded_row("ana", now, report_, recording_);
    ASSERT_EQ(recorded_.result, QStringLiteral("success")) << report_.toStdString();
    ASSERT_TRUE(store_->add_session(recorded_).ok());
    ASSERT_TRUE(store_
                    ->add_session(session_row("ben", now.addSecs(-3600), metrics_report(20.0, 0.5),
                                              {}, "success"))
                    .ok());
  }

  void screenshot(QWidget* w, const QString& name) {
    const QString out = qEnvironmentVariable("LAP_REVIEW_SCREENSHOTS");
    if (out.isEmpty()) return;
    QTest::qWait(300);
    // The screen's pixels: the 3D view is a native window VTK draws into, which grab() misses.
    const QRect r = w->frameGeometry();
    w->screen()
        ->grabWindow(0, r.x(), r.y(), r.width(), r.height())
        .save(out + QLatin1Char('/') + name);
  }

  QTemporaryDir dir_;
  QString recording_;
  QString report_;
  SessionRow recorded_;
  std::unique_ptr<SessionStore> store_;
};

void click_item(QListWidget* list, const QString& text) {
  for (int i = 0; i < list->count(); ++i) {
    if (list->item(i)->text() == text) {
      const QRect r = list->visualItemRect(list->item(i));
      QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, r.center());
      return;
    }
  }
  ADD_FAILURE() << "no item " << text.toStdString();
}

// Clicks the session table's row whose trainee is `trainee` and start is the newest.
void click_row(QTableView* table, int row) {
  const QRect r = table->visualRect(table->model()->index(row, 0));
  QTest::mouseClick(table->viewport(), Qt::LeftButton, {}, r.center());
}

TEST_F(ReviewWindowTest, AnInstructorReviewsASessionAndExportsIt) {
  ReviewWindow window(store_.get(), Viewer::trainee(QString()));
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  EXPECT_EQ(window.trainee_list()->count(), 0);  // nobody signed in: nothing to see
  ASSERT_TRUE(window.sign_in(QStringLiteral("dr-lee"), QStringLiteral("wrong-password"))
                  .diagnostics()
                  .size() == 1);
  EXPECT_FALSE(window.viewer().is_instructor());
  ASSERT_TRUE(window.sign_in(QStringLiteral("dr-lee"), kPassword).ok());
  EXPECT_TRUE(window.viewer().is_instructor());
  // All trainees, ana, ben.
  ASSERT_EQ(window.trainee_list()->count(), 3);
  EXPECT_EQ(window.visible_sessions(), 4);

  // Search and filter.
  QTest::keyClicks(window.search_box(), QStringLiteral("ben"));
  EXPECT_EQ(window.visible_sessions(), 1);
  window.search_box()->clear();
  window.result_filter()->setFocus();
  window.result_filter()->setCurrentIndex(
      window.result_filter()->findData(QStringLiteral("failure")));
  EXPECT_EQ(window.visible_sessions(), 1);
  window.result_filter()->setCurrentIndex(0);

  click_item(window.trainee_list(), QStringLiteral("ana"));
  ASSERT_EQ(window.visible_sessions(), 3);
  // Newest first: the recorded session is the first row. Its recording kept frames (LAPREC05):
  // they are shown in the 3D replay before the replay for the metrics ends.
  std::vector<std::string> order;
  double frames_duration_s = 0.0;
  bool scrubbable = false;
  QObject::connect(&window, &ReviewWindow::recorded_frames_shown, [&](double duration_s) {
    order.emplace_back("frames");
    frames_duration_s = duration_s;
    scrubbable = window.player()->has_timeline() && window.player()->scrub_bar()->isEnabled() &&
                 window.player()->scrub_bar()->maximum() == std::lround(duration_s * 1e3);
  });
  QObject::connect(&window, &ReviewWindow::replay_finished,
                   [&](bool) { order.emplace_back("replay"); });
  click_row(window.session_table(), 0);
  ASSERT_TRUE(wait_until([&] { return window.replay_ready(); }, 180000));
  ASSERT_TRUE(window.timeline() != nullptr) << window.replay_status().toStdString();
  const sim::ReplayTimeline& timeline = *window.timeline();
  EXPECT_GT(timeline.size(), 100U);  // 20 frames a second over about 16 s
  EXPECT_EQ(order, (std::vector<std::string>{"frames", "replay"}));
  EXPECT_TRUE(scrubbable);
  // Ten frames a second, to the session's end (the replay's last frame within 0.1 s of it).
  EXPECT_NEAR(frames_duration_s, timeline.duration_s(), 0.1);

  // The metrics, stored and replayed (a --fast session replays exactly), with verdicts.
  QTableWidget* metrics = window.metrics_table();
  ASSERT_GT(metrics->rowCount(), 10);
  int verdicts = 0;
  for (int i = 0; i < metrics->rowCount(); ++i) {
    const QString name = metrics->item(i, ReviewWindow::kMetricName)->text();
    EXPECT_EQ(metrics->item(i, ReviewWindow::kMetricStored)->text(),
              metrics->item(i, ReviewWindow::kMetricReplayed)->text())
        << name.toStdString();
    if (const QTableWidgetItem* verdict = metrics->item(i, ReviewWindow::kMetricVerdict)) {
      ++verdicts;
      EXPECT_TRUE(verdict->text() == "pass" || verdict->text() == "FAIL");
      EXPECT_EQ(verdicts, i + 1) << "the benchmarked metrics come first";
    }
  }
  EXPECT_EQ(verdicts, 7);  // the introductory scenario's seven benchmarks

  // The plots: the series, the injury threshold, the events.
  SessionCharts* charts = window.charts();
  // Every sample of the replay's series is drawn (fewer than SessionCharts::kMaxPoints: none
  // thinned): force and squeeze, both tools' speeds, the depth.
  const size_t samples = timeline.session().metrics.series.t_s.size();
  ASSERT_GT(samples, 100U);
  ASSERT_LT(samples, SessionCharts::kMaxPoints);
  EXPECT_EQ(charts->data_points(0), static_cast<int>(2 * samples));
  EXPECT_EQ(charts->data_points(1), static_cast<int>(2 * samples));
  EXPECT_EQ(charts->data_points(2), static_cast<int>(samples));
  bool threshold = false, events = false;
  for (QAbstractSeries* s : charts->chart(0)->series()) {
    threshold = threshold || s->name().startsWith(QStringLiteral("injury threshold"));
    events = events || s->name() == QStringLiteral("events");
  }
  EXPECT_TRUE(threshold);
  EXPECT_TRUE(events);

  // Play, then pause: the replay moves and the plots' cursor with it.
  ReplayPlayer* player = window.player();
  QTest::mouseClick(player->play_button(), Qt::LeftButton);
  EXPECT_TRUE(player->playing());
  ASSERT_TRUE(wait_until([&] { return player->time_s() > 0.3; }, 10000));
  QTest::mouseClick(player->play_button(), Qt::LeftButton);
  EXPECT_FALSE(player->playing());
  EXPECT_DOUBLE_EQ(charts->cursor_s(), player->time_s());
  // Scrub with the keys: to the end, back to the start, a page on.
  player->scrub_bar()->setFocus();
  QTest::keyClick(player->scrub_bar(), Qt::Key_End);
  EXPECT_NEAR(player->time_s(), timeline.duration_s(), 1e-3);
  EXPECT_EQ(player->frame(), timeline.size() - 1);
  EXPECT_DOUBLE_EQ(charts->cursor_s(), player->time_s());
  QTest::keyClick(player->scrub_bar(), Qt::Key_Home);
  EXPECT_EQ(player->frame(), 0U);
  EXPECT_DOUBLE_EQ(charts->cursor_s(), 0.0);
  const double page_s = player->scrub_bar()->pageStep() / 1e3;
  QTest::keyClick(player->scrub_bar(), Qt::Key_PageUp);  // Qt: Page Up adds a page
  EXPECT_NEAR(player->time_s(), page_s, 1e-3);
  EXPECT_EQ(player->frame(), timeline.seek(page_s));
  // The frame shown is the timeline's at that time.
  EXPECT_LE(timeline.frame(player->frame()).t_s, page_s + 1e-9);
  // Speed: 4× from the box, with the keyboard.
  player->speed_box()->setFocus();
  QTest::keyClick(player->speed_box(), Qt::Key_End);
  EXPECT_DOUBLE_EQ(player->speed(), 4.0);
  QTest::keyClick(player->scrub_bar(), Qt::Key_PageUp);
  for (int i = 0; i < 8; ++i) QTest::keyClick(player->scrub_bar(), Qt::Key_PageUp);
  EXPECT_NEAR(charts->cursor_s(), 10.0 * page_s, 1e-3);  // ten pages from the start
  screenshot(&window, QStringLiteral("review-session.png"));

  // Exports.
  const QString out = dir_.path() + QStringLiteral("/export");
  ASSERT_TRUE(QDir().mkpath(out));
  ASSERT_TRUE(window.export_session_metrics_csv(out + "/metrics.csv").ok());
  const QStringList metric_lines = read_text(out + "/metrics.csv").split('\n', Qt::SkipEmptyParts);
  EXPECT_EQ(metric_lines.front(), QStringLiteral("metric,value,limit,better,met"));
  EXPECT_EQ(metric_lines.size(), metrics->rowCount() + 1);
  ASSERT_TRUE(window.export_series_csv(out + "/series.csv").ok());
  const QStringList series_lines = read_text(out + "/series.csv").split('\n', Qt::SkipEmptyParts);
  EXPECT_EQ(static_cast<size_t>(series_lines.size()),
            timeline.session().metrics.series.t_s.size() + 1);
  ASSERT_TRUE(window.export_session_json(out + "/session.json").ok());
  const nlohmann::json j = nlohmann::json::parse(read_text(out + "/session.json").toStdString());
  EXPECT_EQ(j["session"]["uuid"], recorded_.uuid.toStdString());
  EXPECT_EQ(j["replay"]["series"]["t_s"].size(), timeline.session().metrics.series.t_s.size());
  EXPECT_EQ(j["report"]["metrics"], j["replay"]["metrics"]);  // --fast: replayed exactly
  ASSERT_TRUE(window.export_trainee_csv(out + "/ana.csv").ok());
  EXPECT_EQ(read_text(out + "/ana.csv").split('\n', Qt::SkipEmptyParts).size(), 4);
  for (const char* pdf : {"session.pdf", "ana.pdf"}) {
    const QString file = out + QLatin1Char('/') + QLatin1String(pdf);
    ASSERT_TRUE((QLatin1String(pdf) == QLatin1String("session.pdf")
                     ? window.export_session_pdf(file)
                     : window.export_trainee_pdf(file))
                    .ok());
    EXPECT_TRUE(read_text(file).startsWith(QStringLiteral("%PDF-1.4")));
    // pdftoppm (poppler-utils) renders it: a valid PDF with its plots.
    QProcess render;
    render.start(QStringLiteral("pdftoppm"),
                 {QStringLiteral("-png"), QStringLiteral("-r"), QStringLiteral("60"), file,
                  file + QStringLiteral("-page")});
    ASSERT_TRUE(render.waitForFinished(60000));
    EXPECT_EQ(render.exitCode(), 0) << render.readAllStandardError().toStdString();
    EXPECT_TRUE(QFile::exists(file + QStringLiteral("-page-1.png")) ||
                QFile::exists(file + QStringLiteral("-page-01.png")));
  }
  const QString shots = qEnvironmentVariable("LAP_REVIEW_SCREENSHOTS");
  if (!shots.isEmpty()) {
    for (const char* pdf : {"session.pdf", "ana.pdf"}) {
      QProcess::execute(QStringLiteral("pdftoppm"),
                        {QStringLiteral("-png"), QStringLiteral("-r"), QStringLiteral("80"),
                         out + QLatin1Char('/') + QLatin1String(pdf),
                         shots + QStringLiteral("/review-") + QString::fromLatin1(pdf).chopped(4)});
    }
  }

  // The learning curve: ana's three sessions against the experts' band.
  window.tabs()->tabBar()->setFocus();
  QTest::mouseClick(window.tabs()->tabBar(), Qt::LeftButton, {},
                    window.tabs()->tabBar()->tabRect(1).center());
  ASSERT_EQ(window.tabs()->currentIndex(), 1);
  QComboBox* metric = window.curve_metric_box();
  // (The largest force on the duct: the overshoot, a failure, has no completion time.)
  metric->setCurrentIndex(metric->findData(QStringLiteral("max_force_duct_n")));
  bool drawn = false;
  for (QAbstractSeries* s : window.learning_chart()->series()) {
    if (s->name() == QStringLiteral("sessions")) {
      drawn = true;
      EXPECT_EQ(static_cast<QXYSeries*>(s)->count(), 3);
    }
  }
  EXPECT_TRUE(drawn);
  screenshot(&window, QStringLiteral("review-learning-curve.png"));
  // The cohort: a curve per trainee.
  QTest::mouseClick(window.tabs()->tabBar(), Qt::LeftButton, {},
                    window.tabs()->tabBar()->tabRect(2).center());
  ASSERT_EQ(window.tabs()->currentIndex(), 2);
  QComboBox* cohort = window.cohort_metric_box();
  cohort->setCurrentIndex(cohort->findData(QStringLiteral("completion_time_s")));
  int trainees = 0;
  for (QAbstractSeries* s : window.cohort_chart()->series()) {
    trainees += (s->name() == QStringLiteral("ana") || s->name() == QStringLiteral("ben")) ? 1 : 0;
  }
  EXPECT_EQ(trainees, 2);
  screenshot(&window, QStringLiteral("review-cohort.png"));
}

TEST_F(ReviewWindowTest, ATraineeSeesTheirOwnSessionsOnly) {
  ReviewWindow window(store_.get(), Viewer::trainee(QStringLiteral("ben")));
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  ASSERT_EQ(window.trainee_list()->count(), 1);
  EXPECT_EQ(window.trainee_list()->item(0)->text(), QStringLiteral("ben"));
  EXPECT_EQ(window.visible_sessions(), 1);
  EXPECT_FALSE(window.tabs()->isTabEnabled(2));  // the cohort is instructors'
  EXPECT_FALSE(window.sign_in(QStringLiteral("dr-lee"), QStringLiteral("not-it")).ok());
  EXPECT_EQ(window.visible_sessions(), 1);
  ASSERT_TRUE(window.sign_in(QStringLiteral("dr-lee"), kPassword).ok());
  EXPECT_EQ(window.trainee_list()->count(), 3);  // All trainees, ana, ben
  EXPECT_EQ(window.visible_sessions(), 1);       // still on ben, whom the window showed
  click_item(window.trainee_list(), QStringLiteral("All trainees"));
  EXPECT_EQ(window.visible_sessions(), 4);
  EXPECT_TRUE(window.tabs()->isTabEnabled(2));
  window.sign_out();
  EXPECT_EQ(window.visible_sessions(), 1);
  // A session without a recording: its stored metrics, and the plots say why there are none.
  click_row(window.session_table(), 0);
  ASSERT_TRUE(wait_until([&] { return window.replay_ready(); }, 10000));
  EXPECT_TRUE(window.timeline() == nullptr);
  EXPECT_GT(window.metrics_table()->rowCount(), 0);
  EXPECT_TRUE(window.replay_status().contains(QStringLiteral("no recording")));
}

}  // namespace
}  // namespace lap::app

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
