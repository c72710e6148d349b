#pragma once
/// \file
/// A Qt widget that hosts a VTK render window in its native X11 window. Debian's VTK Qt module
/// targets Qt5, so instead of QVTKOpenGLNativeWidget this small adapter hands the widget's window
/// id to VTK and forwards Qt's mouse and keyboard events to camera moves itself.

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <QPoint>
#include <QWidget>
#include <string>
#include <vector>

#include "app/scaled_scene_pass.h"
#include "core/result.h"
#include "hardware/mouse_nudge.h"
#include "hardware/tool_nudge.h"

namespace lap::app {

/// A move of the laparoscope asked for by the keys or the mouse (OperativeView applies it to
/// the scope: sim/runtime/laparoscope.h).
enum class ScopeMove {
  kPivot,            ///< a: to the right [rad], b: up [rad], about the port
  kInsert,           ///< a: in (+) or out (−) [m]
  kRoll,             ///< a: the scope (and an angled optic) about its axis [rad]
  kHorizon,          ///< a: the camera head, turning the picture [rad]
  kZoom,             ///< a: factor (> 1 closer)
  kReset,            ///< back to the scenario's view
  kToggleAssistant,  ///< the camera assistant on or off
};
struct ScopeCommand {
  ScopeMove move = ScopeMove::kReset;
  double a = 0.0;
  double b = 0.0;
};

/// Camera pose the view shows when no laparoscope drives it (the organs alone, when a session
/// could not start).
struct CameraPose {
  double position[3] = {0.0, 0.25, 0.35};
  double focal_point[3] = {0.0, 0.03, 0.0};
  double view_up[3] = {0.0, 1.0, 0.0};
  double view_angle_deg = 30.0;
};

/// The 3D view through the laparoscope. Keys and mouse move the scope (scope_command): arrows or
/// left drag pivot it about its port, W/S or right drag slide it in and out, A/D or middle drag
/// (Shift+left) turn it about its axis (an angled optic's view turns with it), Q/E turn the
/// camera head (the picture's horizon), +/- or the wheel zoom, C switches the camera assistant,
/// R resets. With Ctrl held the mouse drives the active tool instead (tool_nudged; the table is
/// hardware/mouse_nudge.h's): the left button and the wheel move it (Shift: the wheel's quarter
/// step), the middle button (or Shift+left) turns it about its shaft, the right button opens and
/// closes its jaws.
/// Before each frame it emits about_to_render, for whoever draws the scene.
class VtkView : public QWidget {
  Q_OBJECT

 public:
  explicit VtkView(QWidget* parent = nullptr);
  ~VtkView() override;

  vtkRenderer* renderer() { return renderer_; }
  vtkRenderWindow* render_window() { return render_window_; }

  /// The pose shown while no laparoscope drives the view; applied now.
  void set_home_camera(const CameraPose& pose);
  /// Back to the scenario's view: the scope's (scope_command kReset) when one drives the view,
  /// else the home pose.
  void reset_camera();
  /// Whether a laparoscope drives the camera (scope_command is connected and acted on).
  void set_scope_driven(bool driven) { scope_driven_ = driven; }
  /// Renders now if the native window exists.
  void render();
  /// Writes the current frame as PNG; the diagnostic says why it could not.
  [[nodiscard]] lap::Status save_png(const QString& file);
  /// Frames rendered so far.
  [[nodiscard]] long frames() const { return frames_; }
  /// The 3D scene drawn at `scale` of the window's size and stretched onto it, the 2D overlays
  /// at full size (ScaledScenePass); 1 draws it at the window's size with VTK's own passes.
  void set_scene_scale(double scale);
  [[nodiscard]] double scene_scale() const { return scene_scale_; }
  /// The scale the 3D picture is drawn at: scene_scale(), or 1 where the driver gave no
  /// off-screen buffer (ScaledScenePass's fallback).
  [[nodiscard]] double drawn_scene_scale() const;
  /// The OpenGL renderer's name (GL_RENDERER), known once the first frame was drawn ("" before).
  [[nodiscard]] const std::string& gl_renderer() const { return gl_renderer_; }
  /// When each frame was done [s, steady clock] (for `laptrainer --stats`).
  [[nodiscard]] const std::vector<double>& frame_times_s() const { return frame_times_s_; }

  QPaintEngine* paintEngine() const override { return nullptr; }

 signals:
  void frame_rendered();
  /// Just before each frame is drawn (the scene is brought up to date here).
  void about_to_render();
  /// A move of the scope (keys, mouse).
  void scope_command(const lap::app::ScopeCommand& command);
  /// The mouse with Ctrl held, for the active tool: a Ctrl+left drag (in the view's plane) or
  /// Ctrl+wheel (along the line of sight) moves its handle, a Ctrl+middle or Ctrl+Shift+left drag
  /// sideways turns it about its shaft, a Ctrl+right drag opens or closes its jaws.
  void tool_nudged(const lap::hardware::ToolNudge& nudge);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;
  void showEvent(QShowEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;

 private:
  void attach();
  void scope(ScopeMove move, double a, double b = 0.0);

  vtkNew<vtkRenderer> renderer_;
  vtkSmartPointer<vtkRenderWindow> render_window_;
  CameraPose home_;
  bool attached_ = false;
  bool scope_driven_ = false;
  QPoint last_mouse_;
  Qt::MouseButtons buttons_ = Qt::NoButton;
  long frames_ = 0;
  std::vector<double> frame_times_s_;
  double scene_scale_ = 1.0;
  vtkSmartPointer<ScaledScenePass> scaled_pass_;
  std::string gl_renderer_;
};

}  // namespace lap::app
