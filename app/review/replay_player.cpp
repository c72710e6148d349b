#include "app/review/replay_player.h"

#include <vtkLight.h>
#include <vtkNew.h>

#include <QComboBox>
#include <QHBoxLayout>
#include <QKeySequence>
#include <QLabel>
#include <QSlider>
#include <QTimer>
#include <QToolButton>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "app/vtk_view.h"

namespace lap::app {

namespace {

// The transport redraws at 30 frames a second while playing (the timeline holds 20 a second:
// a frame is shown until the next one's time).
constexpr int kPlayIntervalMs = 33;
constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};

}  // namespace

ReplayPlayer::ReplayPlayer(QWidget* parent) : QWidget(parent) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  view_ = new VtkView(this);
  view_->setMinimumSize(320, 240);
  layout->addWidget(view_, 1);
  auto* bar = new QHBoxLayout();
  play_button_ = new QToolButton(this);
  play_button_->setObjectName(QStringLiteral("play"));
  play_button_->setText(tr("Play"));
  play_button_->setToolTip(tr("Play or pause the replay (Space)"));
  play_button_->setShortcut(QKeySequence(Qt::Key_Space));
  slider_ = new QSlider(Qt::Horizontal, this);
  slider_->setObjectName(QStringLiteral("scrub"));
  slider_->setRange(0, 0);     // milliseconds of session time
  slider_->setSingleStep(50);  // the arrow keys: a frame (ReplayTimeline::kDefaultFramePeriodS)
  slider_->setPageStep(1000);  // Page Up/Down: a second
  slider_->setToolTip(tr("Scrub through the session"));
  speed_box_ = new QComboBox(this);
  speed_box_->setObjectName(QStringLiteral("speed"));
  for (const double s : kSpeeds) speed_box_->addItem(QStringLiteral("%1×").arg(s), s);
  speed_box_->setCurrentIndex(2);
  time_label_ = new QLabel(this);
  time_label_->setMinimumWidth(110);
  bar->addWidget(play_button_);
  bar->addWidget(slider_, 1);
  bar->addWidget(speed_box_);
  bar->addWidget(time_label_);
  layout->addLayout(bar);
  timer_ = new QTimer(this);
  timer_->setInterval(kPlayIntervalMs);
  connect(timer_, &QTimer::timeout, this, &ReplayPlayer::tick);
  connect(play_button_, &QToolButton::clicked, this, [this] { playing() ? pause() : play(); });
  connect(slider_, &QSlider::valueChanged, this, [this](int ms) {
    if (!slider_driven_) seek(ms / 1000.0);
  });
  connect(speed_box_, &QComboBox::currentIndexChanged, this,
          [this](int i) { set_speed(speed_box_->itemData(i).toDouble()); });
  set_timeline(nullptr);
}

ReplayPlayer::~ReplayPlayer() = default;

void ReplayPlayer::set_timeline(std::shared_ptr<const sim::ReplayTimeline> timeline) {
  pause();
  timeline_ = std::move(timeline);
  vtkRenderer* ren = view_->renderer();
  ren->RemoveAllViewProps();
  actors_ = std::make_unique<SessionActors>();
  t_s_ = 0.0;
  frame_ = 0;
  const bool usable = timeline_ != nullptr && timeline_->size() > 0;
  play_button_->setEnabled(usable);
  slider_->setEnabled(usable);
  slider_driven_ = true;
  slider_->setRange(0, usable ? static_cast<int>(std::lround(timeline_->duration_s() * 1e3)) : 0);
  slider_->setValue(0);
  slider_driven_ = false;
  if (usable) {
    const sim::ReplayScene& scene = timeline_->scene();
    ren->RemoveAllLights();
    vtkNew<vtkLight> light;  // a headlight, as the laparoscope's own light
    light->SetLightTypeToHeadlight();
    ren->AddLight(light);
    CameraPose pose;
    for (int i = 0; i < 3; ++i) {
      pose.position[i] = scene.camera.position_m[i];
      pose.focal_point[i] = scene.camera.focal_point_m[i];
      pose.view_up[i] = scene.camera.view_up[i];
    }
    pose.view_angle_deg = scene.camera.view_angle_deg;
    view_->set_home_camera(pose);
    // What the live view draws (session_actors.h), from what the replay kept of the scene.
    actors_->add(ren, replay_drawing(scene));
    show_frame(0);
  }
  update_label();
  view_->render();
}

void ReplayPlayer::seek(double t_s) {
  if (!timeline_ || timeline_->size() == 0) return;
  t_s_ = std::clamp(t_s, 0.0, timeline_->duration_s());
  show_frame(timeline_->seek(t_s_));
  slider_driven_ = true;
  slider_->setValue(static_cast<int>(std::lround(t_s_ * 1e3)));
  slider_driven_ = false;
  update_label();
  view_->render();
  emit time_changed(t_s_);
}

void ReplayPlayer::show_frame(size_t i) {
  frame_ = i;
  timeline_->snapshots(i, &haptic_, &model_);
  actors_->update(haptic_, model_);
}

bool ReplayPlayer::playing() const { return timer_->isActive(); }

void ReplayPlayer::play() {
  if (!timeline_ || timeline_->size() == 0) return;
  if (t_s_ >= timeline_->duration_s()) seek(0.0);  // from the start again
  clock_.start();
  timer_->start();
  play_button_->setText(tr("Pause"));
}

void ReplayPlayer::pause() {
  timer_->stop();
  play_button_->setText(tr("Play"));
}

void ReplayPlayer::set_speed(double factor) {
  speed_ = factor > 0.0 ? factor : 1.0;
  for (int i = 0; i < speed_box_->count(); ++i) {
    if (std::abs(speed_box_->itemData(i).toDouble() - speed_) < 1e-9 &&
        speed_box_->currentIndex() != i) {
      speed_box_->setCurrentIndex(i);
    }
  }
}

void ReplayPlayer::tick() {
  // Session time advances by the wall time since the last tick times the speed, so that a slow
  // frame does not slow the replay down.
  const double wall_s = static_cast<double>(clock_.restart()) / 1e3;
  const double next = t_s_ + wall_s * speed_;
  seek(next);
  if (next >= timeline_->duration_s()) pause();
}

void ReplayPlayer::update_label() {
  const double end = timeline_ ? timeline_->duration_s() : 0.0;
  time_label_->setText(QStringLiteral("%1 / %2 s").arg(t_s_, 0, 'f', 2).arg(end, 0, 'f', 2));
}

}  // namespace lap::app
