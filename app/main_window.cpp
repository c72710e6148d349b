#include "app/main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QFileDialog>
#include <QGuiApplication>
#include <QHBoxLayout>
#include <QHash>
#include <QMenuBar>
#include <QMessageBox>
#include <QScreen>
#include <QSet>
#include <QStatusBar>
#include <QTimer>
#include <QVBoxLayout>
#include <filesystem>
#include <iostream>
#include <string>

#include "app/authoring/authoring_panel.h"
#include "app/pages/page_style.h"
#include "app/review/review_window.h"
#include "hardware/device_spec.h"
#include "sim/report/session_report.h"

namespace lap::app {
namespace fs = std::filesystem;

namespace {

constexpr const char* kStepNames[] = {"Sign in",  "Patient", "Instruments",
                                      "Briefing", "Run",     "Result"};

bool plays_back(const hardware::DeviceSpec& s) {
  return (s.kind == hardware::DeviceKind::kScripted || s.kind == hardware::DeviceKind::kReplay) &&
         !s.usb_gripper;
}

}  // namespace

MainWindow::MainWindow() {
  setWindowTitle("laptrainer");
  setMinimumSize(1024, 680);
  resize(1280, 800);

  auto* central = new QWidget(this);
  auto* v = new QVBoxLayout(central);
  v->setContentsMargins(0, 0, 0, 0);
  v->setSpacing(0);
  build_step_bar();
  v->addWidget(step_bar_);
  stack_ = new QStackedWidget(central);
  v->addWidget(stack_, 1);
  setCentralWidget(central);

  sign_in_ = new SignInPage(stack_);
  scenarios_ = new ScenarioPage(stack_);
  devices_ = new DevicesPage(stack_);
  briefing_ = new BriefingPage(stack_);
  run_ = new RunPage(stack_);
  result_ = new ResultPage(stack_);
  for (QWidget* page :
       std::initializer_list<QWidget*>{sign_in_, scenarios_, devices_, briefing_, run_, result_}) {
    stack_->addWidget(page);
  }

  connect(sign_in_, &SignInPage::signed_in, this, &MainWindow::sign_in);
  connect(scenarios_, &ScenarioPage::chosen, this, &MainWindow::choose_scenario);
  connect(scenarios_, &ScenarioPage::open_file_requested, this, &MainWindow::open_scenario_dialog);
  connect(devices_, &DevicesPage::accepted, this, &MainWindow::devices_chosen);
  connect(devices_, &DevicesPage::back, this, [this] { go(Step::kScenario); });
  connect(briefing_, &BriefingPage::start_requested, this, &MainWindow::start_attempt);
  connect(briefing_, &BriefingPage::back, this, [this] { go(Step::kDevices); });
  connect(run_, &RunPage::ended, this, &MainWindow::attempt_ended);
  connect(run_, &RunPage::restart_requested, this, &MainWindow::restart_attempt);
  connect(run_, &RunPage::end_requested, this, &MainWindow::end_attempt_by_trainee);
  connect(result_, &ResultPage::next_attempt, this, [this] {
    if (direct_) {
      (void)open_scenario(QString::fromStdString(scenario_.file.string()));
    } else {
      go(Step::kBriefing);
    }
  });
  connect(result_, &ResultPage::another_patient, this, &MainWindow::show_scenarios);
  connect(result_, &ResultPage::sign_out, this, &MainWindow::sign_out);

  build_menus();
  scene_label_ = new QLabel(this);
  fps_label_ = new QLabel(this);
  loops_label_ = new QLabel(this);
  statusBar()->addWidget(scene_label_, 1);
  statusBar()->addPermanentWidget(loops_label_);
  statusBar()->addPermanentWidget(fps_label_);
  if (run_->operative()->has_space_mouse()) {
    auto* mouse_label = new QLabel("3D mouse", this);
    mouse_label->setToolTip(
        "A 3D mouse (spacenavd) steers and turns the active tool (T switches tools)");
    statusBar()->addPermanentWidget(mouse_label);
  }
  connect(run_->operative(), &OperativeView::figures_updated, this, &MainWindow::update_status);

  // The session database: the trainees' attempts. Without it the window still trains; the
  // result page says why no attempts are shown.
  Result<std::unique_ptr<SessionStore>> opened = SessionStore::open_default();
  if (opened.ok()) {
    store_ = std::move(opened).value();
  } else {
    store_problem_ = QString::fromStdString(opened.message());
    std::cerr << "laptrainer: the session database did not open: " << opened.message() << "\n";
  }

  // What the station remembers.
  device_texts_ = settings_.devices();
  dominant_hand_ = settings_.dominant_hand();
  set_render_quality(
      parse_render_quality(settings_.render_quality()).value_or(RenderQualityChoice::kAuto), false);
  if (const QByteArray g = settings_.window_geometry(); !g.isEmpty()) restoreGeometry(g);
  if (settings_.full_screen()) {
    full_screen_action_->setChecked(true);
    QTimer::singleShot(0, this, [this] { showFullScreen(); });
  }
  sign_in_->set_known_trainees(known_trainees());
  sign_in_->set_trainee(settings_.last_trainee());
  go(Step::kSignIn);
  // Attempts a crash (or a kill) left unfiled, filed as interrupted: after the window is up.
  QTimer::singleShot(0, this, &MainWindow::file_unfiled_attempts);
}

MainWindow::~MainWindow() = default;

void MainWindow::build_step_bar() {
  step_bar_ = new QWidget(this);
  step_bar_->setObjectName("step_bar");
  step_bar_->setAttribute(Qt::WA_StyledBackground);
  step_bar_->setStyleSheet(
      "QWidget#step_bar { background: #151a20; border-bottom: 1px solid #323c48; }");
  auto* h = new QHBoxLayout(step_bar_);
  h->setContentsMargins(20, 8, 16, 8);
  h->setSpacing(6);
  auto* brand = new QLabel("<b>laptrainer</b>", step_bar_);
  brand->setStyleSheet(QString("color: %1; font-size: 12pt; margin-right: 18px;").arg(kAccent));
  h->addWidget(brand);
  for (size_t i = 0; i < std::size(kStepNames); ++i) {
    if (i > 0) {
      auto* sep = new QLabel("›", step_bar_);
      sep->setStyleSheet("color: #4a5663;");
      h->addWidget(sep);
    }
    auto* l = new QLabel(QString("%1  %2").arg(i + 1).arg(kStepNames[i]), step_bar_);
    step_labels_.push_back(l);
    h->addWidget(l);
  }
  h->addStretch(1);
  trainee_label_ = new QLabel(step_bar_);
  trainee_label_->setObjectName("signed_in_as");
  trainee_label_->setStyleSheet("color: #9aa7b4;");
  h->addWidget(trainee_label_);
}

void MainWindow::build_menus() {
  QMenu* file = menuBar()->addMenu("&File");
  sign_out_action_ = file->addAction("Sign &Out", this, &MainWindow::sign_out);
  choose_action_ =
      file->addAction("&Choose Patient...", QKeySequence::New, this, &MainWindow::show_scenarios);
  file->addAction("&Open Scenario File...", QKeySequence::Open, this,
                  &MainWindow::open_scenario_dialog);
  file->addAction("Save &Screenshot...", QKeySequence("Ctrl+Shift+S"), this,
                  &MainWindow::screenshot_dialog);
  // The instructor's review opens as its own window (app/review/README.md): the signed-in
  // trainee's own sessions, or everyone's once an instructor signs in there.
  file->addAction("&Review Sessions...", this, [this] {
    Result<ReviewWindow*> review = ReviewWindow::open_default(trainee_);
    if (review.ok()) {
      review.value()->show();
    } else {
      QMessageBox::warning(this, "Review", QString::fromStdString(review.message()));
    }
  });
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, this, &QWidget::close);

  QMenu* view_menu = menuBar()->addMenu("&View");
  full_screen_action_ = view_menu->addAction("&Full Screen", QKeySequence::FullScreen, this,
                                             &MainWindow::toggle_full_screen);
  full_screen_action_->setCheckable(true);
  // F11 as well where the desktop's own full-screen key is another.
  if (QKeySequence(QKeySequence::FullScreen) != QKeySequence(Qt::Key_F11)) {
    full_screen_action_->setShortcuts({QKeySequence::FullScreen, QKeySequence(Qt::Key_F11)});
  }
  reset_camera_action_ = view_menu->addAction("&Reset Camera", QKeySequence("R"), this,
                                              [this] { view()->reset_camera(); });
  QAction* wire = view_menu->addAction("&Wireframe", QKeySequence("Ctrl+Shift+W"), this, [this] {
    wireframe_ = !wireframe_;
    run_->operative()->set_wireframe(wireframe_);
  });
  wire->setCheckable(true);
  // On a station without a GPU the full picture is slow (render_quality.h).
  QMenu* quality = view_menu->addMenu("Picture &Quality");
  auto* quality_group = new QActionGroup(this);
  const std::array<std::pair<const char*, RenderQualityChoice>, 3> qualities = {{
      {"&Automatic (fast on a software renderer)", RenderQualityChoice::kAuto},
      {"&Full", RenderQualityChoice::kFull},
      {"F&ast (no GPU)", RenderQualityChoice::kFast},
  }};
  for (size_t k = 0; k < qualities.size(); ++k) {
    const RenderQualityChoice choice = qualities[k].second;
    QAction* a = quality->addAction(qualities[k].first, this,
                                    [this, choice] { set_render_quality(choice, true); });
    a->setCheckable(true);
    a->setData(static_cast<int>(choice));
    quality_group->addAction(a);
    quality_actions_[k] = a;
  }

  QMenu* session = menuBar()->addMenu("&Session");
  pause_action_ = session->addAction("&Pause / Resume", this, [this] { run_->toggle_pause(); });
  pause_action_->setShortcuts({QKeySequence(Qt::Key_P), QKeySequence(Qt::Key_Escape)});
  restart_action_ =
      session->addAction("&Restart", QKeySequence("Ctrl+R"), this, &MainWindow::restart_attempt);
  end_action_ = session->addAction("&End Attempt", QKeySequence("Ctrl+E"), this,
                                   &MainWindow::end_attempt_by_trainee);
  session->addSeparator();
  home_action_ = session->addAction("Instrument &Home", QKeySequence("H"), this, [this] {
    run_->session().go_home(run_->operative()->active_tool());
  });
  home_action_->setToolTip("Takes the keyboard-driven instrument back to where it started");
  devices_action_ = session->addAction("&Device Set-up...", this, [this] {
    if (scene_) go(Step::kDevices);
  });

  // Scenario authoring (app/authoring/authoring_panel.h): a dock, hidden until asked for; it
  // runs the scenario it opens at once, as the command line's session (open_scenario).
  authoring_ = new AuthoringPanel([this](const QString& f) { return open_scenario(f); },
                                  [this] { return run_->operative()->session().session(); }, this);
  addDockWidget(Qt::RightDockWidgetArea, authoring_);
  authoring_->hide();
  QMenu* authoring = menuBar()->addMenu("&Authoring");
  authoring->addAction("&Open Scenario...", this, [this] {
    const QString f =
        QFileDialog::getOpenFileName(this, "Open scenario", QString(), "Scenarios (*.yaml *.yml)");
    if (f.isEmpty()) return;
    authoring_->show();
    authoring_->open(f);
  });
  QAction* mode = authoring_->toggleViewAction();
  mode->setText("Authoring &Mode");
  authoring->addAction(mode);

  QMenu* help = menuBar()->addMenu("&Help");
  help->addAction("&Controls", QKeySequence::HelpContents, this, &MainWindow::show_controls);
  help->addAction("&About laptrainer", this, [this] {
    QMessageBox::about(this, "About laptrainer",
                       "<b>laptrainer</b> 0.1.0<br>Laparoscopic cholecystectomy training "
                       "simulator: catheter insertion into the cystic duct.<br>Haptic rendering "
                       "after Ho &amp; Srinivasan, MIT 1999.");
  });
}

void MainWindow::go(Step step) {
  if (step_ == Step::kRun && step != Step::kRun && attempt_running_) {
    (void)finish_session(false);  // leaving the run ends it (saved and filed)
  }
  step_ = step;
  QWidget* pages[] = {sign_in_, scenarios_, devices_, briefing_, run_, result_};
  stack_->setCurrentWidget(pages[static_cast<int>(step)]);
  for (size_t i = 0; i < step_labels_.size(); ++i) {
    const bool current = static_cast<int>(i) == static_cast<int>(step);
    const bool done = static_cast<int>(i) < static_cast<int>(step);
    step_labels_[i]->setStyleSheet(current
                                       ? QString("color: %1; font-weight: 600;").arg(kAccent)
                                       : QString("color: %1;").arg(done ? "#c4ced8" : "#5d6a77"));
  }
  step_bar_->setVisible(step != Step::kRun);
  trainee_label_->setText(trainee_.isEmpty() ? QString()
                                             : QString("Signed in as %1").arg(trainee_));
  if (step == Step::kSignIn) sign_in_->focus_field();
  if (step == Step::kDevices && scene_) devices_->set_scene(&*scene_);
  if (step == Step::kBriefing) briefing_->set_briefing(scenario_, device_texts_);
  update_actions();
  update_status();
}

void MainWindow::update_actions() {
  const bool run = step_ == Step::kRun;
  for (QAction* a :
       {pause_action_, restart_action_, end_action_, home_action_, reset_camera_action_}) {
    a->setEnabled(run);
  }
  sign_out_action_->setEnabled(!trainee_.isEmpty());
  choose_action_->setEnabled(!trainee_.isEmpty() || direct_);
  devices_action_->setEnabled(scene_.has_value() && !direct_ && !trainee_.isEmpty());
}

void MainWindow::sign_in(const QString& trainee) {
  trainee_ = trainee;
  direct_ = false;
  settings_.remember_trainee(trainee);
  settings_.sync();
  if (store_) {
    if (const Status added = store_->add_trainee(trainee); !added.ok()) {
      std::cerr << "laptrainer: " << added.message() << "\n";
    }
  }
  show_scenarios();
}

void MainWindow::set_render_quality(RenderQualityChoice choice, bool remember) {
  run_->operative()->set_render_quality(choice);
  for (QAction* a : quality_actions_) {
    if (a != nullptr && a->data().toInt() == static_cast<int>(choice)) a->setChecked(true);
  }
  if (remember) settings_.set_render_quality(render_quality_name(choice));
}

void MainWindow::sign_out() {
  if (attempt_running_) (void)finish_session(false);
  trainee_.clear();
  sign_in_->set_known_trainees(known_trainees());
  sign_in_->set_trainee(settings_.last_trainee());
  go(Step::kSignIn);
}

void MainWindow::show_scenarios() {
  if (trainee_.isEmpty()) {
    go(Step::kSignIn);
    return;
  }
  std::vector<CatalogEntry> entries = scan_scenarios(scenarios_folder());
  const QString last = settings_.last_scenario();
  bool listed = false;
  for (const CatalogEntry& e : entries) {
    listed = listed || QString::fromStdString(e.file.string()) == last;
  }
  std::error_code ec;
  if (!listed && !last.isEmpty() && fs::is_regular_file(last.toStdString(), ec)) {
    entries.push_back(catalog_entry(last.toStdString()));  // opened from elsewhere before
  }
  scenarios_->set_trainee(trainee_);
  scenarios_->set_scenarios(entries, last);
  go(Step::kScenario);
}

void MainWindow::open_scenario_dialog() {
  const QString file =
      QFileDialog::getOpenFileName(this, "Open scenario", QString(), "Scenarios (*.yaml *.yml)");
  if (file.isEmpty()) return;
  if (trainee_.isEmpty() || direct_) {
    if (const Status opened = open_scenario(file); !opened.ok()) {
      QMessageBox::warning(this, "Scenario not loaded", QString::fromStdString(opened.message()));
    }
    return;
  }
  const CatalogEntry entry = catalog_entry(file.toStdString());
  if (!entry.problems.empty()) {
    QMessageBox::warning(this, "Scenario not loaded", QString::fromStdString(entry.problems));
    return;
  }
  choose_scenario(entry);
}

void MainWindow::choose_scenario(const CatalogEntry& entry) {
  QApplication::setOverrideCursor(Qt::WaitCursor);
  sim::SceneLoadResult r = sim::load_scene_file(entry.file);
  QApplication::restoreOverrideCursor();
  if (!r.ok()) {
    QMessageBox::warning(this, "Scenario not loaded", QString::fromStdString(r.message()));
    return;
  }
  devices_->set_scene(nullptr);
  scene_ = std::move(r).value();
  scenario_ = entry;
  settings_.set_last_scenario(QString::fromStdString(entry.file.string()));
  setWindowTitle(QString("laptrainer - %1").arg(QString::fromStdString(entry.name)));
  devices_->set_specs(device_texts_);
  devices_->set_dominant_hand(dominant_hand_);
  go(Step::kDevices);
}

void MainWindow::devices_chosen(const std::array<QString, 2>& specs, int dominant_hand) {
  device_texts_ = specs;
  dominant_hand_ = dominant_hand;
  settings_.set_devices(specs);
  settings_.set_dominant_hand(dominant_hand);
  go(Step::kBriefing);
}

std::array<hardware::DeviceSpec, 2> MainWindow::parsed_devices() const {
  std::array<hardware::DeviceSpec, 2> out{};
  for (size_t i = 0; i < 2; ++i) {
    const auto parsed = hardware::parse_device_spec(device_texts_[i].toStdString());
    if (parsed.ok()) out[i] = parsed.value();
  }
  return out;
}

void MainWindow::start_attempt() {
  if (!scene_ || trainee_.isEmpty()) return;
  const Result<fs::path> root = recordings_root();
  if (!root.ok()) {
    QMessageBox::warning(this, "Cannot start", QString::fromStdString(root.message()));
    return;
  }
  const QString devices = QString("left=%1; right=%2").arg(device_texts_[0], device_texts_[1]);
  Result<SessionRow> begun =
      begin_attempt(root.value(), trainee_, scenario_.file, QString::fromStdString(scenario_.name),
                    devices, store_ ? store_->connection().station : QString());
  if (!begun.ok()) {
    QMessageBox::warning(this, "Cannot start", QString::fromStdString(begun.message()));
    return;
  }
  attempt_ = std::move(begun).value();
  const std::array<hardware::DeviceSpec, 2> specs = parsed_devices();
  LiveSessionOptions options;
  options.end_with_task = true;
  options.record_dir = attempt_.recording_dir.toStdString();
  options.dominant_tool = dominant_hand_;
  options.fast = fast_playback_ && plays_back(specs[0]) && plays_back(specs[1]);
  direct_ = false;
  go(Step::kRun);
  const QString who =
      QString("<b>%1</b> &nbsp;·&nbsp; %2")
          .arg(QString::fromStdString(scenario_.name).toHtmlEscaped(), trainee_.toHtmlEscaped());
  // Running before the session starts: a fast session may end, and say so, while start() still
  // draws its first frame (events are processed there), and its end must find the attempt.
  attempt_running_ = true;
  const Status started = run_->start(*scene_, specs, options, who);
  if (!started.ok()) {
    attempt_running_ = false;
    // Nothing was recorded: the attempt's folder goes.
    std::error_code ec;
    fs::remove_all(attempt_.recording_dir.toStdString(), ec);
    attempt_ = SessionRow{};
    go(Step::kDevices);
    QMessageBox::warning(this, "The session did not start",
                         QString::fromStdString(started.message()));
    return;
  }
  update_status();
}

void MainWindow::restart_attempt() {
  if (step_ != Step::kRun) return;
  if (direct_) {
    (void)finish_session(false);
    (void)open_scenario(QString::fromStdString(scenario_.file.string()));
    return;
  }
  (void)finish_session(false);
  start_attempt();
}

void MainWindow::attempt_ended() { (void)finish_session(true); }

void MainWindow::end_attempt_by_trainee() {
  if (step_ != Step::kRun) return;
  (void)finish_session(true);
}

Status MainWindow::end_session() { return finish_session(false); }

Status MainWindow::finish_session(bool show) {
  LiveSession& s = run_->session();
  if (!s.running()) return {};
  const bool attempt = attempt_running_;
  attempt_running_ = false;
  const std::string dir =
      attempt ? attempt_.recording_dir.toStdString() : record_dir_.toStdString();
  Status saved;
  if (dir.empty()) {
    s.stop();
  } else {
    saved = s.stop_and_save(dir);
  }
  const nlohmann::ordered_json report =
      sim::metrics_to_json(s.last_metrics(), s.scenario_file(), s.options().fast);
  if (attempt) {
    finish_attempt(report, &attempt_);
    if (const Status filed = file(attempt_); !filed.ok()) {
      std::cerr << "laptrainer: " << filed.message() << "\n";
    }
  }
  if (!saved.ok()) {
    std::cerr << "laptrainer: " << saved.message() << "\n";
    if (show) {
      QMessageBox::warning(this, "Session not saved", QString::fromStdString(saved.message()));
    }
  }
  if (show) {
    const SessionRow shown = attempt ? attempt_ : [&] {
      SessionRow r;
      finish_attempt(report, &r);
      r.recording_dir = record_dir_;
      return r;
    }();
    QString why;
    const std::vector<SessionRow> attempts =
        attempt ? attempts_on(attempt_.scenario_file, &why) : std::vector<SessionRow>{};
    result_->show_result(report, shown, attempts);
    if (!attempt) {
      result_->show_attempts_unavailable(
          "Started from the command line without signing in: this attempt is not filed.");
    } else if (!why.isEmpty()) {
      result_->show_attempts_unavailable(why);
    }
    go(Step::kResult);
  }
  return saved;
}

Status MainWindow::open_scenario(const QString& file) {
  sim::SceneLoadResult r = sim::load_scene_file(file.toStdString());
  if (!r.ok()) return r.diagnostics();
  if (run_->session().running()) (void)finish_session(false);
  scene_ = std::move(r).value();
  scenario_ = catalog_entry(file.toStdString());
  direct_ = true;
  setWindowTitle(QString("laptrainer - %1").arg(QString::fromStdString(scene_->scenario.name)));
  LiveSessionOptions options;
  options.end_with_task = true;
  options.record_dir = record_dir_.toStdString();
  go(Step::kRun);
  const QString who = QString("<b>%1</b> &nbsp;·&nbsp; started from the command line")
                          .arg(QString::fromStdString(scene_->scenario.name).toHtmlEscaped());
  const Status started = run_->start(*scene_, cli_devices_, options, who);
  if (!started.ok()) {
    loops_label_->setText(
        QString("loops not started: %1").arg(QString::fromStdString(started.message())));
  }
  update_status();
  return started;
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (const Status ended = finish_session(false); !ended.ok()) {
    std::cerr << "laptrainer: " << ended.message() << "\n";
  }
  devices_->stop_test();
  settings_.set_full_screen(isFullScreen());
  if (!isFullScreen()) settings_.set_window_geometry(saveGeometry());
  settings_.sync();
  QMainWindow::closeEvent(event);
}

void MainWindow::toggle_full_screen() {
  if (isFullScreen()) {
    showNormal();
  } else {
    settings_.set_window_geometry(saveGeometry());
    showFullScreen();
  }
  full_screen_action_->setChecked(isFullScreen());
}

void MainWindow::screenshot_dialog() {
  const QString file =
      QFileDialog::getSaveFileName(this, "Save screenshot", "laptrainer.png", "PNG images (*.png)");
  if (file.isEmpty()) return;
  // The operative field as rendered while running; the page itself otherwise.
  const Status saved =
      step_ == Step::kRun
          ? view()->save_png(file)
          : (grab().save(file, "PNG") ? Status{}
                                      : Status(diagnostic("cannot write " + file.toStdString())));
  if (!saved.ok())
    QMessageBox::warning(this, "Screenshot", QString::fromStdString(saved.message()));
}

void MainWindow::show_controls() {
  QMessageBox box(this);
  box.setWindowTitle("Controls");
  box.setTextFormat(Qt::RichText);
  box.setText(
      "<b>Instruments driven by the keyboard and mouse</b><br>"
      "T switches between the left and right hand. J/L move the hand's handle left/right, I/K "
      "away/towards you, U/O up/down, 2 mm a press (the tip moves the other way: the shaft "
      "pivots in its port). [ closes the jaws, ] opens them; , and . turn the instrument about "
      "its shaft, 5° a press (the jaws' plane turns with it). With Shift each key goes a quarter "
      "as far, to aim finely. H takes the instrument home.<br>"
      "Ctrl+left drag moves it in the view's plane, Ctrl+wheel along the view (with Shift a "
      "quarter as far), Ctrl+middle drag (or Ctrl+Shift+left drag) sideways turns it about its "
      "shaft, Ctrl+right drag up opens the jaws and down closes them. A 3D mouse "
      "moves it in three dimensions and a twist of its cap turns it about its shaft; its buttons "
      "close and open the jaws.<br><br>"
      "<b>The laparoscope</b><br>Left drag or the arrows pivot it about its port, right drag or "
      "W/S slide it in and out, middle drag (or Shift+left) or A/D turn it (a 30° scope's view "
      "turns with it), Q/E turn the picture's horizon, the wheel or +/- zoom. C switches the "
      "camera assistant (the scope follows the instruments); R resets the scope.<br><br>"
      "<b>The session</b><br>P or Esc pauses (no force, the clock stops); Space resumes, also "
      "after the safety watchdog paused the session. Ctrl+R restarts the patient, Ctrl+E ends "
      "the attempt. F11 toggles full screen.");
  box.exec();
}

void MainWindow::update_status() {
  if (step_ != Step::kRun || !scene_) {
    scene_label_->setText(trainee_.isEmpty() ? "Not signed in"
                                             : QString("Signed in as %1").arg(trainee_));
    fps_label_->clear();
    loops_label_->clear();
    return;
  }
  scene_label_->setText(QString("%1: %2 organs, %3 triangles")
                            .arg(QString::fromStdString(scene_->scenario.name))
                            .arg(scene_->organs.size())
                            .arg(scene_->triangle_count()));
  const OperativeView* o = run_->operative();
  fps_label_->setText(QString("%1 frames/s").arg(o->frame_rate(), 0, 'f', 0));
  if (run_->session().running()) {
    loops_label_->setText(o->loops_text());
    loops_label_->setToolTip(o->loops_tooltip());
  }
}

// --- The session database (app/store): the trainee's attempts. ---

std::vector<SessionRow> MainWindow::attempts_on(const QString& scenario_file, QString* why) const {
  if (!store_) {
    *why = "The session database is not available: " + store_problem_;
    return {};
  }
  Result<std::vector<SessionRow>> rows = store_->sessions(trainee_, scenario_file);
  if (!rows.ok()) {
    *why = QString::fromStdString(rows.message());
    return {};
  }
  why->clear();
  return std::move(rows).value();
}

QStringList MainWindow::known_trainees() const {
  // This station's, most recent first, then the database's (a programme's server: everyone's).
  QStringList out = settings_.recent_trainees();
  if (store_) {
    const Result<std::vector<QString>> all = store_->trainees();
    if (all.ok()) {
      for (const QString& t : all.value()) {
        if (!out.contains(t)) out << t;
      }
    }
  }
  return out;
}

Status MainWindow::file(const SessionRow& record) {
  if (!store_) return diagnostic("not filed: " + store_problem_.toStdString());
  return store_->add_session(record);
}

void MainWindow::file_unfiled_attempts() {
  if (!store_) return;
  const Result<fs::path> root = recordings_root();
  if (!root.ok()) return;
  // Filed already: by uuid, among the sessions of the trainee each folder names.
  QHash<QString, QSet<QString>> filed;
  const UnfiledAttempts found = unfiled_attempts(root.value(), [&](const SessionRow& header) {
    if (!filed.contains(header.trainee)) {
      QSet<QString>& uuids = filed[header.trainee];
      const Result<std::vector<SessionRow>> rows = store_->sessions(header.trainee);
      if (!rows.ok()) return true;  // cannot tell: left for the next start
      for (const SessionRow& r : rows.value()) uuids.insert(r.uuid);
    }
    return filed[header.trainee].contains(header.uuid);
  });
  for (const std::string& problem : found.problems) {
    std::cerr << "laptrainer: an attempt's folder could not be read: " << problem << "\n";
  }
  int count = 0;
  for (const SessionRow& r : found.records) {
    if (const Status added = store_->add_session(r); !added.ok()) {
      std::cerr << "laptrainer: " << added.message() << "\n";
    } else {
      ++count;
    }
  }
  if (count > 0) {
    statusBar()->showMessage(QString("%1 attempt(s) cut short earlier (the program stopped) "
                                     "filed as interrupted")
                                 .arg(count),
                             15000);
  }
}

}  // namespace lap::app
