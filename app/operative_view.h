#pragma once
/// \file
/// The operative field of a running session: the 3D view (VtkView), the session it shows
/// (LiveSession: the haptic and modelling loops on their threads), what is drawn of it
/// (SessionActors: organs, instruments, catheter), the laparoscope it is seen through
/// (sim/runtime/laparoscope.h: moved by the keys and the mouse, or by the camera assistant;
/// LaparoscopeCamera), the heads-up display (HudModel, HudOverlay), and the graphics loop — a
/// 60 Hz timer that renders; before each frame the newest snapshots are taken into the actors,
/// the scope and the display. The keys and the 3D mouse that drive simulated tools are handled
/// here, so that any page that shows a session behaves the same.
///
/// The window around it (menus, status bar, the pages of a training session) only starts,
/// stops and saves sessions through this widget, and reads its figures (loops_text()).

#include <QElapsedTimer>
#include <QString>
#include <QWidget>
#include <array>
#include <memory>
#include <optional>
#include <string>

#include "app/hud_overlay.h"
#include "app/hud_state.h"
#include "app/laparoscope_camera.h"
#include "app/live_session.h"
#include "app/render_quality.h"
#include "app/session_actors.h"
#include "app/vtk_view.h"
#include "core/result.h"
#include "hardware/device_spec.h"
#include "hardware/space_mouse.h"
#include "sim/runtime/camera_assistant.h"
#include "sim/runtime/laparoscope.h"
#include "sim/setup/scene.h"

namespace lap::app {

class OperativeView : public QWidget {
  Q_OBJECT

 public:
  explicit OperativeView(QWidget* parent = nullptr);
  ~OperativeView() override;
  OperativeView(const OperativeView&) = delete;
  OperativeView& operator=(const OperativeView&) = delete;
  OperativeView(OperativeView&&) = delete;
  OperativeView& operator=(OperativeView&&) = delete;

  /// Stops any running session, shows `scene` and starts a session on it with `devices`. When
  /// the loops cannot start, the organs are still shown and the diagnostics say why.
  [[nodiscard]] Status start(const sim::Scene& scene,
                             const std::array<hardware::DeviceSpec, 2>& devices);
  /// Ends the running session without saving it.
  void stop();
  /// Ends the running session and saves it into `dir` (LiveSession::stop_and_save).
  [[nodiscard]] Status stop_and_save(const std::string& dir);

  [[nodiscard]] LiveSession& session() { return session_; }
  [[nodiscard]] VtkView* view() { return view_; }
  /// The tool the keys and the 3D mouse move: 0 left, 1 right.
  [[nodiscard]] int active_tool() const { return active_tool_; }
  void set_active_tool(int tool);
  /// Frames per second over the last second, and the loops' figures as one line (rates, the
  /// haptic loop's worst lateness and late ticks, PAUSED, BEST EFFORT timing).
  [[nodiscard]] double frame_rate() const { return frame_rate_; }
  [[nodiscard]] const QString& loops_text() const { return loops_text_; }
  [[nodiscard]] const QString& loops_tooltip() const { return loops_tooltip_; }
  /// Whether a 3D mouse (spacenavd) drives the active tool.
  [[nodiscard]] bool has_space_mouse() const { return space_mouse_ != nullptr; }
  /// Draws the organs as wireframes (true) or surfaces.
  void set_wireframe(bool on);
  /// Whether the heads-up display is drawn over the field (true by default; false for the
  /// scenario chooser's previews, `laptrainer --no-hud`). The session's state runs either way.
  void set_hud_shown(bool shown);
  /// How the picture is drawn (render_quality.h), from the next frame; auto decides on the first
  /// frame's renderer.
  void set_render_quality(RenderQualityChoice choice);
  /// The profile the last frame was drawn with.
  [[nodiscard]] const RenderProfile& render_profile_in_use() const { return profile_; }

  /// The laparoscope (null before a scene is shown, or when the scenario's camera cannot be a
  /// scope through its port: the view then stays at the scenario's camera).
  [[nodiscard]] const sim::LaparoscopeModel* scope_model() const {
    return scope_model_ ? &*scope_model_ : nullptr;
  }
  [[nodiscard]] const sim::LaparoscopeState& scope_state() const { return scope_; }
  /// Moves the scope as the keys and the mouse do.
  void move_scope(const ScopeCommand& command);
  /// The camera assistant keeps the instruments' tips in view (§7.8; key C).
  void set_camera_assistant(bool on);
  [[nodiscard]] bool camera_assistant() const { return assistant_on_; }
  /// What the heads-up display shows (null before a session runs).
  [[nodiscard]] const HudState* hud_state() const { return hud_ ? &hud_->state() : nullptr; }
  [[nodiscard]] const HudOverlay& hud_overlay() const { return overlay_; }
  [[nodiscard]] const SessionActors& actors() const { return actors_; }

 signals:
  /// Once a second: the frame rate and the loops' figures have been updated.
  void figures_updated();

 protected:
  void keyPressEvent(QKeyEvent* event) override;

 private:
  void graphics_frame();
  void draw_scene();
  void update_figures();
  void apply_render_profile();

  VtkView* view_ = nullptr;
  LiveSession session_;
  SessionActors actors_;
  std::optional<sim::LaparoscopeModel> scope_model_;
  sim::LaparoscopeState scope_;
  sim::CameraAssistant assistant_;
  bool assistant_on_ = false;
  LaparoscopeCamera camera_;
  std::unique_ptr<HudModel> hud_;
  HudOverlay overlay_;
  double last_draw_s_ = -1.0;
  int active_tool_ = 0;
  int64_t last_haptic_tick_ = -1;
  int64_t last_model_steps_ = 0;
  long last_frames_ = 0;
  QElapsedTimer figures_clock_;
  double frame_rate_ = 0.0;
  QString loops_text_;
  QString loops_tooltip_;
  bool wireframe_ = false;
  bool hud_shown_ = true;
  RenderQualityChoice quality_ = RenderQualityChoice::kAuto;
  RenderProfile profile_;
  bool profile_applied_ = false;
  double last_frame_s_ = 0.0;
  // A 3D mouse, when spacenavd and libspnav are there: it steers the active tool like the keys.
  std::unique_ptr<hardware::SpaceMouse> space_mouse_;
  hardware::SpaceMouseMapping space_mouse_mapping_;
};

}  // namespace lap::app
