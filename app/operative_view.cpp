#include "app/operative_view.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkProperty.h>

#include <QElapsedTimer>
#include <QKeyEvent>
#include <QStringList>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <vector>

#include "app/mesh_actor.h"

namespace lap::app {
namespace {

double seconds_since_start() {
  static QElapsedTimer clock;
  if (!clock.isValid()) clock.start();
  return static_cast<double>(clock.nsecsElapsed()) * 1e-9;
}

}  // namespace

OperativeView::OperativeView(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  view_ = new VtkView(this);
  layout->addWidget(view_);
  setFocusProxy(view_);
  connect(view_, &VtkView::tool_moved, this, [this](double dx, double dy, double dz) {
    session_.nudge(active_tool_, Eigen::Vector3d(dx, dy, dz), 0.0);
  });

  auto mouse = hardware::SpaceMouse::open();
  if (mouse.ok()) space_mouse_ = std::move(mouse).value();

  // The graphics loop (docs/architecture.md: Qt event loop, 30-60 Hz): redraw at 60 Hz so that
  // moving tools and deforming organs appear as the other loops publish them.
  auto* frame_timer = new QTimer(this);
  frame_timer->setTimerType(Qt::PreciseTimer);
  connect(frame_timer, &QTimer::timeout, this, &OperativeView::graphics_frame);
  frame_timer->start(1000 / 60);

  auto* figures_timer = new QTimer(this);
  connect(figures_timer, &QTimer::timeout, this, &OperativeView::update_figures);
  figures_timer->start(1000);
}

OperativeView::~OperativeView() { session_.stop(); }

Status OperativeView::start(const sim::Scene& scene,
                            const std::array<hardware::DeviceSpec, 2>& devices) {
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
  std::vector<Eigen::Vector3d> colours;
  for (const sim::Organ& o : scene.organs) colours.push_back(o.color);
  const Status started = session_.start(scene, devices);
  if (started.ok()) {
    // The organs as the session has them (the duct: its shell), deformed as the loops go.
    std::vector<const haptics::TriangleMesh*> surfaces;
    for (int32_t i = 0; i < session_.organ_count(); ++i) {
      surfaces.push_back(&session_.organ_surface(i));
    }
    actors_.add_organs(ren, surfaces, colours);
    actors_.add_to(ren, {session_.tool_geometry(0), session_.tool_geometry(1)},
                   static_cast<int>(session_.model().catheter.size()));
  } else {
    for (const sim::Organ& o : scene.organs) {
      const double rgb[3] = {o.color.x(), o.color.y(), o.color.z()};
      ren->AddActor(make_mesh_actor(o.mesh, rgb));
    }
  }
  set_wireframe(wireframe_);
  last_haptic_tick_ = -1;
  last_model_steps_ = 0;
  update_figures();
  return started;
}

void OperativeView::stop() { session_.stop(); }

Status OperativeView::stop_and_save(const std::string& dir) { return session_.stop_and_save(dir); }

void OperativeView::set_active_tool(int tool) {
  active_tool_ = std::clamp(tool, 0, 1);
  update_figures();
}

void OperativeView::set_wireframe(bool on) {
  wireframe_ = on;
  vtkActorCollection* actors = view_->renderer()->GetActors();
  actors->InitTraversal();
  while (vtkActor* a = actors->GetNextActor()) {
    if (on) {
      a->GetProperty()->SetRepresentationToWireframe();
    } else {
      a->GetProperty()->SetRepresentationToSurface();
    }
  }
  view_->render();
}

void OperativeView::graphics_frame() {
  const double now_s = seconds_since_start();
  if (space_mouse_) {
    const double dt = std::clamp(now_s - last_frame_s_, 0.0, 0.1);  // a stalled UI must not jump
    const hardware::ToolNudge n =
        hardware::space_mouse_nudge(space_mouse_->poll(now_s), space_mouse_mapping_, dt);
    if (!n.delta_W.isZero() || n.opening_rad != 0.0) {
      session_.nudge(active_tool_, n.delta_W, n.opening_rad);
    }
  }
  last_frame_s_ = now_s;
  if (session_.running()) actors_.update(session_.haptic(), session_.model());
  view_->render();
}

void OperativeView::update_figures() {
  const double s =
      figures_clock_.isValid() ? static_cast<double>(figures_clock_.restart()) / 1000.0 : 0.0;
  if (!figures_clock_.isValid()) figures_clock_.start();
  const long f = view_->frames();
  if (s > 0.0) frame_rate_ = static_cast<double>(f - last_frames_) / std::max(s, 1e-3);
  last_frames_ = f;
  if (!session_.running()) {
    loops_text_ = "no session";
    loops_tooltip_.clear();
    emit figures_updated();
    return;
  }
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
  loops_tooltip_.clear();
  const std::vector<std::string> warnings = session_.scheduling_warnings();
  if (!warnings.empty()) {
    // The loops run best effort: their timing figures are worth reading with that in mind.
    QStringList all;
    for (const std::string& w : warnings) all << QString::fromStdString(w);
    text = QString("BEST EFFORT timing | ") + text;
    loops_tooltip_ = all.join("\n");
  }
  if (h.paused) {
    text = QString("PAUSED (%1): forces off, Space resumes | ")
               .arg(QString::fromStdString(
                   sim::describe(h.last_reason, h.last_model_fault, session_.organ_names()))) +
           text;
  }
  loops_text_ = text;
  emit figures_updated();
}

void OperativeView::keyPressEvent(QKeyEvent* e) {
  constexpr double kStep = 0.002;    // m per press
  constexpr double kOpening = 0.05;  // rad per press
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  double opening = 0.0;
  switch (e->key()) {
    case Qt::Key_T:
      set_active_tool(1 - active_tool_);
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
      QWidget::keyPressEvent(e);
      return;
  }
  session_.nudge(active_tool_, d, opening);
}

}  // namespace lap::app
