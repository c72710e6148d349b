#include "app/operative_view.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkProperty.h>

#include <QElapsedTimer>
#include <QKeyEvent>
#include <QStringList>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <vector>

#include "app/dynamic_resolution.h"
#include "app/mesh_actor.h"
#include "app/tool_keys.h"

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
  connect(view_, &VtkView::tool_nudged, this,
          [this](const hardware::ToolNudge& n) { session_.nudge(active_tool_, n); });
  connect(view_, &VtkView::scope_command, this, &OperativeView::move_scope);
  connect(view_, &VtkView::about_to_render, this, &OperativeView::draw_scene);

  // LAP_SPNAV_LIBRARY names another libspnav: one installed elsewhere, or a test's stand-in.
  // Without a 3D mouse the application runs as well; one asked for by name and not opened is
  // said on the terminal.
  const char* spnav = std::getenv("LAP_SPNAV_LIBRARY");
  const bool named = spnav != nullptr && *spnav != '\0';
  auto mouse = named ? hardware::SpaceMouse::open(spnav) : hardware::SpaceMouse::open();
  if (mouse.ok()) {
    space_mouse_ = std::move(mouse).value();
  } else if (named) {
    qWarning("laptrainer: LAP_SPNAV_LIBRARY: %s", mouse.message().c_str());
  }

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
  // The scenario's camera, shown as is when it cannot be a scope through its port.
  CameraPose pose;
  const sim::CameraSpec& c = scene.scenario.camera;
  for (int i = 0; i < 3; ++i) {
    pose.position[i] = c.position_m[i];
    pose.focal_point[i] = c.focal_point_m[i];
    pose.view_up[i] = c.view_up[i];
  }
  pose.view_angle_deg = c.view_angle_deg;
  Result<sim::LaparoscopeModel> scope = sim::LaparoscopeModel::build(c, scene.scenario.file);
  scope_model_.reset();
  view_->set_scope_driven(false);
  if (scope.ok()) {
    scope_model_ = std::move(scope).value();
    scope_ = scope_model_->home;
    assistant_.reset();
    camera_.attach(ren, scope_model_->focal_distance_m);
    view_->set_scope_driven(true);
  } else {
    camera_.attach(ren, (c.focal_point_m - c.position_m).norm());
  }
  view_->set_home_camera(pose);
  const Status started = session_.start(scene, devices);
  hud_.reset();
  if (started.ok()) {
    // The organs as the session has them (the duct: its shell), deformed as the loops go, the
    // instruments and the catheter.
    actors_.add(ren, session_drawing(scene, session_.session_model()));
    hud_ = std::make_unique<HudModel>(scene.scenario, session_.organ_names());
  } else {
    for (const sim::Organ& o : scene.organs) {
      const double rgb[3] = {o.color.x(), o.color.y(), o.color.z()};
      ren->AddActor(make_mesh_actor(o.mesh, rgb));
    }
  }
  overlay_.attach(ren);
  overlay_.set_visible(hud_ != nullptr && hud_shown_);
  set_wireframe(wireframe_);
  profile_applied_ = false;  // the new actors' textures and lights take the profile
  last_haptic_tick_ = -1;
  last_model_steps_ = 0;
  last_draw_s_ = -1.0;
  update_figures();
  return started;
}

void OperativeView::move_scope(const ScopeCommand& command) {
  if (!scope_model_) return;
  const sim::LaparoscopeModel& m = *scope_model_;
  switch (command.move) {
    case ScopeMove::kPivot:
      sim::pivot_laparoscope(m, &scope_, command.a, command.b);
      break;
    case ScopeMove::kInsert:
      sim::insert_laparoscope(m, &scope_, command.a);
      break;
    case ScopeMove::kRoll:
      sim::roll_laparoscope(&scope_, command.a);
      break;
    case ScopeMove::kHorizon:
      sim::turn_laparoscope_horizon(&scope_, command.a);
      break;
    case ScopeMove::kZoom:
      sim::zoom_laparoscope(m, &scope_, command.a);
      break;
    case ScopeMove::kReset:
      scope_ = m.home;
      assistant_.reset();
      break;
    case ScopeMove::kToggleAssistant:
      set_camera_assistant(!assistant_on_);
      break;
  }
}

void OperativeView::set_camera_assistant(bool on) {
  assistant_on_ = on;
  assistant_.reset();
  update_figures();
}

void OperativeView::stop() { session_.stop(); }

Status OperativeView::stop_and_save(const std::string& dir) { return session_.stop_and_save(dir); }

void OperativeView::set_active_tool(int tool) {
  active_tool_ = std::clamp(tool, 0, 1);
  update_figures();
}

void OperativeView::set_render_quality(RenderQualityChoice choice) {
  quality_ = choice;
  profile_applied_ = false;
}

void OperativeView::apply_render_profile() {
  const RenderProfile wanted = render_profile(quality_, view_->gl_renderer());
  if (profile_applied_ && wanted == profile_) return;
  profile_ = wanted;
  profile_applied_ = true;
  actors_.set_texture_mipmaps(profile_.mipmaps);
  camera_.set_spot_light(profile_.spot_light);
  view_->set_scene_scale(profile_.scene_scale);
}

void OperativeView::set_hud_shown(bool shown) {
  hud_shown_ = shown;
  if (hud_) overlay_.set_visible(hud_shown_);  // else when the session's display is made
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
    if (!n.delta_W.isZero() || n.opening_rad != 0.0 || n.roll_rad != 0.0) {
      session_.nudge(active_tool_, n);
    }
  }
  last_frame_s_ = now_s;
  view_->render();
}

// Before each frame: the newest snapshots into the actors, the scope (the assistant following
// the instruments' tips), its camera and light, and the heads-up display.
void OperativeView::draw_scene() {
  apply_render_profile();
  const double now_s = seconds_since_start();
  const double dt = last_draw_s_ < 0.0 ? 0.0 : std::clamp(now_s - last_draw_s_, 0.0, 0.1);
  last_draw_s_ = now_s;
  if (session_.running()) {
    const sim::HapticSnapshot& h = session_.haptic();
    const sim::ModelSnapshot& m = session_.model();
    actors_.update(h, m);
    if (assistant_on_ && scope_model_ && h.tick >= 0) {
      // The working point: the middle of each instrument's jaws.
      std::array<Eigen::Vector3d, 2> tips;
      for (int i = 0; i < 2; ++i) {
        const InstrumentPose& p = actors_.instrument(i).pose();
        tips[static_cast<size_t>(i)] = 0.5 * (p.hinge_W + 0.5 * (p.jaw_tip_W[0] + p.jaw_tip_W[1]));
      }
      assistant_.step(*scope_model_, &scope_, tips, dt);
    }
    if (hud_ && hud_shown_) {
      ScopeFigures figures;
      if (scope_model_) {
        figures.optics_deg = scope_model_->optic_angle_rad * 180.0 / M_PI;
        figures.zoom = std::tan(0.5 * scope_model_->home.view_angle_deg * M_PI / 180.0) /
                       std::tan(0.5 * scope_.view_angle_deg * M_PI / 180.0);
      }
      figures.assistant = assistant_on_;
      const int* size = view_->render_window()->GetSize();
      overlay_.draw(hud_->update(h, m, figures, now_s), size[0], size[1]);
    }
  }
  if (scope_model_) camera_.apply(sim::laparoscope_view(*scope_model_, scope_));
}

void OperativeView::update_figures() {
  const double s =
      figures_clock_.isValid() ? static_cast<double>(figures_clock_.restart()) / 1000.0 : 0.0;
  if (!figures_clock_.isValid()) figures_clock_.start();
  const long f = view_->frames();
  if (s > 0.0) frame_rate_ = static_cast<double>(f - last_frames_) / std::max(s, 1e-3);
  last_frames_ = f;
  // The fast profile's picture as large as 30 frames/s allow (dynamic resolution).
  // (Only on the once-a-second tick: a call between them, a key's, measures too short a span.)
  if (profile_applied_ && profile_.fast && s >= 0.9) {
    view_->set_scene_scale(next_scene_scale(view_->scene_scale(), frame_rate_));
  }
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
  QString text = QString("haptic %1 Hz (worst late %2 us, %3 late ticks) | model %4 Hz | %5 tool%6")
                     .arg(ticks)
                     .arg(h.worst_lateness_s * 1e6, 0, 'f', 0)
                     .arg(h.late_ticks)
                     .arg(steps)
                     .arg(active_tool_ == 0 ? "left" : "right")
                     .arg(assistant_on_ ? " | camera assistant" : "");
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
  switch (e->key()) {
    case Qt::Key_T:
      set_active_tool(1 - active_tool_);
      return;
    case Qt::Key_Space:
      session_.resume();
      return;
    default:
      break;
  }
  if (const std::optional<hardware::ToolKey> key =
          tool_key(e->key(), static_cast<int>(e->modifiers()))) {
    session_.nudge(active_tool_,
                   hardware::key_nudge(*key, fine_step(static_cast<int>(e->modifiers()))));
    return;
  }
  QWidget::keyPressEvent(e);
}

}  // namespace lap::app
