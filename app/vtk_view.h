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
#include <vector>

#include "core/result.h"

namespace lap::app {

/// Camera pose the view can be reset to.
struct CameraPose {
  double position[3] = {0.0, 0.25, 0.35};
  double focal_point[3] = {0.0, 0.03, 0.0};
  double view_up[3] = {0.0, 1.0, 0.0};
  double view_angle_deg = 30.0;
};

/// The 3D view: orbit with the left button, pan with the middle button or Shift+left, zoom with
/// the right button or the wheel; arrow keys orbit, +/- zoom, W/A/S/D pan, R resets. With Ctrl
/// held, the left button and the wheel move the active tool instead (tool_moved).
class VtkView : public QWidget {
  Q_OBJECT

 public:
  explicit VtkView(QWidget* parent = nullptr);
  ~VtkView() override;

  vtkRenderer* renderer() { return renderer_; }
  vtkRenderWindow* render_window() { return render_window_; }

  /// Sets the pose R returns to and applies it.
  void set_home_camera(const CameraPose& pose);
  void reset_camera();
  /// Renders now if the native window exists.
  void render();
  /// Writes the current frame as PNG; the diagnostic says why it could not.
  [[nodiscard]] lap::Status save_png(const QString& file);
  /// Frames rendered so far.
  [[nodiscard]] long frames() const { return frames_; }
  /// When each frame was done [s, steady clock] (for `laptrainer --stats`).
  [[nodiscard]] const std::vector<double>& frame_times_s() const { return frame_times_s_; }

  QPaintEngine* paintEngine() const override { return nullptr; }

 signals:
  void frame_rendered();
  /// Ctrl+left drag (in the view's plane) or Ctrl+wheel (along the view): a world displacement
  /// [m] for the active tool's handle.
  void tool_moved(double dx, double dy, double dz);

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
  void orbit(double azimuth_deg, double elevation_deg);
  void pan(double dx_px, double dy_px);
  void zoom(double factor);

  vtkNew<vtkRenderer> renderer_;
  vtkSmartPointer<vtkRenderWindow> render_window_;
  CameraPose home_;
  bool attached_ = false;
  QPoint last_mouse_;
  Qt::MouseButtons buttons_ = Qt::NoButton;
  long frames_ = 0;
  std::vector<double> frame_times_s_;
};

}  // namespace lap::app
