#include "app/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDateTime>
#include <QFileDialog>
#include <QMenuBar>
#include <QMessageBox>
#include <QStatusBar>
#include <iostream>
#include <string>

namespace lap::app {

MainWindow::MainWindow() {
  setWindowTitle("laptrainer");
  resize(1024, 720);
  operative_ = new OperativeView(this);
  setCentralWidget(operative_);

  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&Open Scenario...", QKeySequence::Open, this, &MainWindow::open_dialog);
  file->addAction("Save &Screenshot...", QKeySequence("Ctrl+P"), this,
                  &MainWindow::screenshot_dialog);
  file->addAction("&End and Save Session...", QKeySequence::Save, this,
                  &MainWindow::save_session_dialog);
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, qApp, &QApplication::quit);

  QMenu* view = menuBar()->addMenu("&View");
  view->addAction("&Reset Camera", QKeySequence("R"), operative_->view(), &VtkView::reset_camera);
  QAction* wire = view->addAction("&Wireframe", QKeySequence("Ctrl+W"), this, [this] {
    wireframe_ = !wireframe_;
    operative_->set_wireframe(wireframe_);
  });
  wire->setCheckable(true);

  // Scenario authoring (app/authoring/authoring_panel.h): a dock, hidden until asked for.
  authoring_ = new AuthoringPanel([this](const QString& f) { return open_scenario(f); },
                                  [this] { return operative_->session().session(); }, this);
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
  help->addAction("&Controls", this, [this] {
    QMessageBox::information(
        this, "Controls",
        "Mouse: left drag orbits, middle drag (or Shift+left) pans, right drag or wheel zooms.\n"
        "Keys: arrows orbit, +/- zoom, W/A/S/D pan, R resets the camera.\n\n"
        "Tools (simulated devices): Ctrl+left drag moves the active tool's handle in the view's\n"
        "plane, Ctrl+wheel along the view. T switches between the left and right tool. J/L move "
        "the\n"
        "handle left/right, I/K away/towards you, U/O up/down, 2 mm a press (the tip moves the\n"
        "other way: the shaft pivots in its trocar). [ closes the jaws, ] opens them.\n"
        "Space resumes after the safety watchdog paused the session.");
  });
  help->addAction("&About laptrainer", this, [this] {
    QMessageBox::about(this, "About laptrainer",
                       "laptrainer: laparoscopic cholecystectomy training simulator.\n"
                       "Haptic rendering after Ho & Srinivasan, MIT 1999.");
  });

  scene_label_ = new QLabel(this);
  fps_label_ = new QLabel(this);
  statusBar()->addWidget(scene_label_, 1);
  loops_label_ = new QLabel(this);
  statusBar()->addPermanentWidget(loops_label_);
  statusBar()->addPermanentWidget(fps_label_);
  if (operative_->has_space_mouse()) {
    auto* mouse_label = new QLabel("3D mouse", this);
    mouse_label->setToolTip("A 3D mouse (spacenavd) steers the active tool (T switches tools)");
    statusBar()->addPermanentWidget(mouse_label);
  }
  // The frame rate and the loops' figures, once a second.
  connect(operative_, &OperativeView::figures_updated, this, [this] {
    fps_label_->setText(QString("%1 frames/s").arg(operative_->frame_rate(), 0, 'f', 0));
    loops_label_->setText(operative_->loops_text());
    loops_label_->setToolTip(operative_->loops_tooltip());
  });
}

Status MainWindow::open_scenario(const QString& file) {
  sim::SceneLoadResult r = sim::load_scene_file(file.toStdString());
  if (!r.ok()) return r.diagnostics();
  scene_ = std::move(r).value();
  show_scene(scene_);
  return {};
}

void MainWindow::show_scene(const sim::Scene& scene) {
  const Status started = operative_->start(scene, devices_);
  if (!started.ok()) {
    loops_label_->setText(
        QString("loops not started: %1").arg(QString::fromStdString(started.message())));
  }
  setWindowTitle(QString("laptrainer - %1").arg(QString::fromStdString(scene.scenario.name)));
  update_status();
}

Status MainWindow::end_session() {
  if (record_dir_.isEmpty() || !operative_->session().running()) {
    operative_->stop();
    return {};
  }
  return operative_->stop_and_save(record_dir_.toStdString());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (const Status ended = end_session(); !ended.ok()) {
    std::cerr << "laptrainer: " << ended.message() << "\n";
  }
  QMainWindow::closeEvent(event);
}

void MainWindow::save_session_dialog() {
  const QString parent = QFileDialog::getExistingDirectory(this, "Save the session in");
  if (parent.isEmpty()) return;
  // Each saved session in its own folder, named by when it was saved.
  const QString dir =
      parent + "/session-" + QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss");
  if (const Status saved = operative_->stop_and_save(dir.toStdString()); !saved.ok()) {
    QMessageBox::warning(this, "Session not saved", QString::fromStdString(saved.message()));
  } else {
    statusBar()->showMessage(QString("session saved to %1; a new one has started").arg(dir), 10000);
  }
  show_scene(scene_);  // a fresh session on the same scenario
}

void MainWindow::update_status() {
  scene_label_->setText(QString("%1: %2 organs, %3 triangles")
                            .arg(QString::fromStdString(scene_.scenario.name))
                            .arg(scene_.organs.size())
                            .arg(scene_.triangle_count()));
}

void MainWindow::open_dialog() {
  const QString file =
      QFileDialog::getOpenFileName(this, "Open scenario", QString(), "Scenarios (*.yaml *.yml)");
  if (file.isEmpty()) return;
  if (const Status opened = open_scenario(file); !opened.ok()) {
    QMessageBox::warning(this, "Scenario not loaded", QString::fromStdString(opened.message()));
  }
}

void MainWindow::screenshot_dialog() {
  const QString file =
      QFileDialog::getSaveFileName(this, "Save screenshot", "laptrainer.png", "PNG images (*.png)");
  if (file.isEmpty()) return;
  if (const Status saved = operative_->view()->save_png(file); !saved.ok()) {
    QMessageBox::warning(this, "Screenshot", QString::fromStdString(saved.message()));
  }
}

}  // namespace lap::app
