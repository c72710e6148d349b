#pragma once
/// \file
/// The review's 3D replay: a replayed session's frames (sim::ReplayTimeline) drawn with the
/// application's own view and actors (app/vtk_view.h, app/session_actors.h), and its transport —
/// play and pause, a scrub bar, the speed (¼× to 4×), the time. Seeking anywhere is a lookup in
/// the timeline and one update of the actors; time_changed() tells the plots' cursor.

#include <QElapsedTimer>
#include <QWidget>
#include <memory>

#include "app/session_actors.h"
#include "sim/report/replay_timeline.h"

class QComboBox;
class QLabel;
class QSlider;
class QTimer;
class QToolButton;

namespace lap::app {

class VtkView;

class ReplayPlayer : public QWidget {
  Q_OBJECT

 public:
  explicit ReplayPlayer(QWidget* parent = nullptr);
  ~ReplayPlayer() override;
  ReplayPlayer(const ReplayPlayer&) = delete;
  ReplayPlayer& operator=(const ReplayPlayer&) = delete;

  /// Shows a timeline from its start (null: nothing, paused).
  void set_timeline(std::shared_ptr<const sim::ReplayTimeline> timeline);
  [[nodiscard]] bool has_timeline() const { return timeline_ != nullptr; }

  /// Goes to `t_s` (clamped to the session): the frame at or before it.
  void seek(double t_s);
  void play();
  void pause();
  [[nodiscard]] bool playing() const;
  /// Playback speed: 1 is the session's own pace.
  void set_speed(double factor);
  [[nodiscard]] double speed() const { return speed_; }
  [[nodiscard]] double time_s() const { return t_s_; }
  /// The frame shown.
  [[nodiscard]] size_t frame() const { return frame_; }

  [[nodiscard]] VtkView* view() const { return view_; }
  [[nodiscard]] QSlider* scrub_bar() const { return slider_; }
  [[nodiscard]] QToolButton* play_button() const { return play_button_; }
  [[nodiscard]] QComboBox* speed_box() const { return speed_box_; }

 signals:
  /// The replay's time changed (playing, scrubbing, seeking).
  void time_changed(double t_s);

 private:
  void tick();
  void show_frame(size_t i);
  void update_label();

  VtkView* view_ = nullptr;
  QToolButton* play_button_ = nullptr;
  QSlider* slider_ = nullptr;
  QComboBox* speed_box_ = nullptr;
  QLabel* time_label_ = nullptr;
  QTimer* timer_ = nullptr;
  QElapsedTimer clock_;
  std::shared_ptr<const sim::ReplayTimeline> timeline_;
  std::unique_ptr<SessionActors> actors_;
  sim::HapticSnapshot haptic_;
  sim::ModelSnapshot model_;
  double t_s_ = 0.0;
  double speed_ = 1.0;
  size_t frame_ = 0;
  bool slider_driven_ = false;  ///< the slider moves because the replay did: no seek back
};

}  // namespace lap::app
