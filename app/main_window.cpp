#include "app/main_window.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkLight.h>
#include <vtkProperty.h>

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDateTime>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QKeyEvent>
#include <QMenuBar>
#include <QMessageBox>
#include <QStatusBar>
#include <QTimer>
#include <algorithm>
#include <iostream>
#include <memory>
#include <string>

#include "app/mesh_actor.h"

namespace lap::app {

MainWindow::MainWindow() {
  setWindowTitle("laptrainer");
  resize(1024, 720);
  view_ = new VtkView(this);
  setCentralWidget(view_);
  connect(view_, &VtkView::tool_moved, this, [this](double dx, double dy, double dz) {
    session_.nudge(active_tool_, Eigen::Vector3d(dx, dy, dz), 0.0);
  });

  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&Open Scenario...", QKeySequence::Open, this, &MainWindow::open_dialog);
  file->addAction("Save &Screenshot...", QKeySequence("Ctrl+P"), this,
                  &MainWindow::screenshot_dialog);
  file->addAction("&End and Save Session...", QKeySequence::Save, this,
                  &MainWindow::save_session_dialog);
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, qApp, &QApplication::quit);

  QMenu* view = menuBar()->addMenu("&View");
  view->addAction("&Reset Camera", QKeySequence("R"), view_, &VtkView::reset_camera);
  QAction* wire = view->addAction("&Wireframe", QKeySequence("Ctrl+W"), this, [this] {
    wireframe_ = !wireframe_;
    vtkActorCollection* actors = view_->renderer()->GetActors();
    actors->InitTraversal();
    while (vtkActor* a = actors->GetNextActor()) {
      if (wireframe_) {
        a->GetProperty()->SetRepresentationToWireframe();
      } else {
        a->GetProperty()->SetRepresentationToSurface();
      }
    }
    view_->render();
  });
  wire->setCheckable(true);

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

  // The graphics loop (docs/architecture.md: Qt event loop, 30-60 Hz): redraw at 60 Hz so that
  // moving tools and deforming organs appear as the other loops publish them. A 3D mouse, if there
  // is one, is polled here too and moves the active tool's simulated device like the keys do
  // (hardware/space_mouse.h); without one, nothing changes.
  auto mouse = hardware::SpaceMouse::open();
  if (mouse.ok()) {
    space_mouse_ = std::move(mouse).value();
    auto* mouse_label = new QLabel("3D mouse", this);
    mouse_label->setToolTip("A 3D mouse (spacenavd) steers the active tool (T switches tools)");
    statusBar()->addPermanentWidget(mouse_label);
  }
  auto* frame_timer = new QTimer(this);
  frame_timer->setTimerType(Qt::PreciseTimer);
  auto frame_clock = std::make_shared<QElapsedTimer>();
  frame_clock->start();
  connect(frame_timer, &QTimer::timeout, this, [this, frame_clock, last_s = 0.0]() mutable {
    const double now_s = static_cast<double>(frame_clock->nsecsElapsed()) * 1e-9;
    if (space_mouse_) {
      const double dt = std::clamp(now_s - last_s, 0.0, 0.1);  // a stalled UI must not jump
      const hardware::ToolNudge n =
          hardware::space_mouse_nudge(space_mouse_->poll(now_s), space_mouse_mapping_, dt);
      if (!n.delta_W.isZero() || n.opening_rad != 0.0) {
        session_.nudge(active_tool_, n.delta_W, n.opening_rad);
      }
    }
    last_s = now_s;
    if (session_.running()) actors_.update(session_.haptic(), session_.model());
    view_->render();
  });
  frame_timer->start(1000 / 60);

  // Frame rate shown in the status bar once a second.
  auto* timer = new QTimer(this);
  auto* clock = new QElapsedTimer;
  clock->start();
  auto last_frames = std::make_shared<long>(0);
  connect(timer, &QTimer::timeout, this, [this, clock, last_frames] {
    const double s = clock->restart() / 1000.0;
    const long f = view_->frames();
    fps_label_->setText(
        QString("%1 frames/s").arg((f - *last_frames) / std::max(s, 1e-3), 0, 'f', 0));
    *last_frames = f;
    update_loops();
  });
  timer->start(1000);
}

Status MainWindow::open_scenario(const QString& file) {
  sim::SceneLoadResult r = sim::load_scene_file(file.toStdString());
  if (!r.ok()) return r.diagnostics();
  scene_ = std::move(r).value();
  show_scene(scene_);
  return {};
}

void MainWindow::show_scene(const sim::Scene& scene) {
  session_.stop();
  vtkRenderer* ren = view_->renderer();
  ren->RemoveAllViewProps();
  // A headlight, like the laparoscope's own light source.
  ren->RemoveAllLights();
  vtkNew<vtkLight> light;
  light->SetLightTypeToHeadlight();
  light->SetIntensity(1.0);
  ren->AddLight(light);
  CameraPose pose;
  const sim::CameraSpec& c = scene.scenario.camera;
  for (int i = 0; i < 3; ++i) {
    pose.position[i] = c.position_m[i];
    pose.focal_point[i] = c.focal_point_m[i];
    pose.view_up[i] = c.view_up[i];
  }
  pose.view_angle_deg = c.view_angle_deg;
  view_->set_home_camera(pose);
  // The loops: two simulated tools through their trocars, the catheter.
  std::vector<Eigen::Vector3d> colours;
  for (const sim::Organ& o : scene.organs) colours.push_back(o.color);
  const Status started = session_.start(scene, devices_);
  if (started.ok()) {
    // The organs as the session has them (the duct: its shell), deformed as the loops go.
    std::vector<const haptics::TriangleMesh*> surfaces;
    for (int32_t i = 0; i < session_.organ_count(); ++i)
      surfaces.push_back(&session_.organ_surface(i));
    actors_.add_organs(ren, surfaces, colours);
    actors_.add_to(ren, {session_.tool_geometry(0), session_.tool_geometry(1)},
                   static_cast<int>(session_.model().catheter.size()));
  } else {
    for (const sim::Organ& o : scene.organs) {
      const double rgb[3] = {o.color.x(), o.color.y(), o.color.z()};
      ren->AddActor(make_mesh_actor(o.mesh, rgb));
    }
    loops_label_->setText(
        QString("loops not started: %1").arg(QString::fromStdString(started.message())));
  }
  last_haptic_tick_ = -1;
  last_model_steps_ = 0;
  setWindowTitle(QString("laptrainer - %1").arg(QString::fromStdString(scene.scenario.name)));
  update_status();
}

void MainWindow::update_loops() {
  if (!session_.running()) return;
  const sim::HapticSnapshot& h = session_.haptic();
  const sim::ModelSnapshot& m = session_.model();
  const int64_t ticks = last_haptic_tick_ < 0 ? 0 : h.tick - last_haptic_tick_;
  const int64_t steps = m.steps - last_model_steps_;
  last_haptic_tick_ = h.tick;
  last_model_steps_ = m.steps;
  // Late ticks: each sent zero force for one tick and the forces ramped back by themselves.
  QString text = QString("haptic %1 Hz (worst late %2 us, %3 late ticks) | model %4 Hz | %5 tool")
                     .arg(ticks)
                     .arg(h.worst_lateness_s * 1e6, 0, 'f', 0)
                     .arg(h.late_ticks)
                     .arg(steps)
                     .arg(active_tool_ == 0 ? "left" : "right");
  const std::vector<std::string> warnings = session_.scheduling_warnings();
  if (!warnings.empty()) {
    // The loops run best effort: their timing figures are worth reading with that in mind.
    QStringList all;
    for (const std::string& w : warnings) all << QString::fromStdString(w);
    text = QString("BEST EFFORT timing | ") + text;
    loops_label_->setToolTip(all.join("\n"));
  }
  if (h.paused) {
    text = QString("PAUSED (%1): forces off, Space resumes | ")
               .arg(QString::fromStdString(
                   sim::describe(h.last_reason, h.last_model_fault, session_.organ_names()))) +
           text;
  }
  loops_label_->setText(text);
}

void MainWindow::keyPressEvent(QKeyEvent* e) {
  constexpr double kStep = 0.002;    // m per press
  constexpr double kOpening = 0.05;  // rad per press
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  double opening = 0.0;
  switch (e->key()) {
    case Qt::Key_T:
      active_tool_ = 1 - active_tool_;
      update_loops();
      return;
    case Qt::Key_Space:
      session_.resume();
      return;
    case Qt::Key_J:
      d.x() = -kStep;
      break;
    case Qt::Key_L:
      d.x() = kStep;
      break;
    case Qt::Key_I:
      d.z() = -kStep;
      break;
    case Qt::Key_K:
      d.z() = kStep;
      break;
    case Qt::Key_U:
      d.y() = kStep;
      break;
    case Qt::Key_O:
      d.y() = -kStep;
      break;
    case Qt::Key_BracketLeft:
      opening = -kOpening;
      break;
    case Qt::Key_BracketRight:
      opening = kOpening;
      break;
    default:
      QMainWindow::keyPressEvent(e);
      return;
  }
  session_.nudge(active_tool_, d, opening);
}

Status MainWindow::end_session() {
  if (record_dir_.isEmpty() || !session_.running()) {
    session_.stop();
    return {};
  }
  return session_.stop_and_save(record_dir_.toStdString());
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
  if (const Status saved = session_.stop_and_save(dir.toStdString()); !saved.ok()) {
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
  if (const Status saved = view_->save_png(file); !saved.ok()) {
    QMessageBox::warning(this, "Screenshot", QString::fromStdString(saved.message()));
  }
}

}  // namespace lap::app
