#include "app/vtk_view.h"

#include <vtkCamera.h>
#include <vtkPNGWriter.h>
#include <vtkWindowToImageFilter.h>
#include <vtk_glew.h>

#include <QKeyEvent>
#include <QMouseEvent>
#include <QWheelEvent>
#include <algorithm>
#include <chrono>
#include <cmath>

namespace lap::app {

VtkView::VtkView(QWidget* parent) : QWidget(parent) {
  // VTK draws into this widget's own X window; Qt must neither paint it nor share it.
  setAttribute(Qt::WA_NativeWindow);
  setAttribute(Qt::WA_PaintOnScreen);
  setAttribute(Qt::WA_NoSystemBackground);
  setAttribute(Qt::WA_OpaquePaintEvent);
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(false);
  setMinimumSize(320, 240);
  render_window_ = vtkSmartPointer<vtkRenderWindow>::New();
  render_window_->AddRenderer(renderer_);
  render_window_->SetMultiSamples(0);
  renderer_->SetBackground(0.07, 0.05, 0.05);
  renderer_->SetBackground2(0.22, 0.14, 0.13);
  renderer_->GradientBackgroundOn();
}

VtkView::~VtkView() {
  if (attached_) render_window_->Finalize();
}

void VtkView::attach() {
  if (attached_) return;
  // The native window id is only valid once Qt created the window. The size is set first:
  // vtkXOpenGLRenderWindow resizes the X window on SetSize once it has a window id, and it opens
  // its display connection only in the first Render().
  const qreal dpr = devicePixelRatioF();
  render_window_->SetSize(static_cast<int>(width() * dpr), static_cast<int>(height() * dpr));
  render_window_->SetWindowId(reinterpret_cast<void*>(winId()));
  attached_ = true;
}

void VtkView::render() {
  if (!isVisible()) return;
  if (attached_) {
    const qreal dpr = devicePixelRatioF();
    render_window_->SetSize(static_cast<int>(width() * dpr), static_cast<int>(height() * dpr));
  } else {
    attach();
  }
  emit about_to_render();
  render_window_->Render();
  if (gl_renderer_.empty()) {
    // The context exists once the first frame was drawn. Asked again next frame if it says
    // nothing.
    render_window_->MakeCurrent();
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (name != nullptr) gl_renderer_ = name;
  }
  ++frames_;
  frame_times_s_.push_back(
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
  emit frame_rendered();
}

void VtkView::set_scene_scale(double scale) {
  scale = std::clamp(scale, 0.25, 1.0);
  if (scale == scene_scale_) return;
  scene_scale_ = scale;
  if (scale >= 1.0) {
    renderer_->SetPass(nullptr);
    if (scaled_pass_) scaled_pass_->ReleaseGraphicsResources(render_window_);
    return;
  }
  if (!scaled_pass_) scaled_pass_ = vtkSmartPointer<ScaledScenePass>::New();
  scaled_pass_->set_scale(scale);
  renderer_->SetPass(scaled_pass_);
}

double VtkView::drawn_scene_scale() const {
  const bool scaled = scene_scale_ < 1.0 && scaled_pass_ && !scaled_pass_->unavailable();
  return scaled ? scene_scale_ : 1.0;
}

void VtkView::set_home_camera(const CameraPose& pose) {
  home_ = pose;
  reset_camera();
}

void VtkView::reset_camera() {
  if (scope_driven_) {
    scope(ScopeMove::kReset, 0.0);
    return;
  }
  vtkCamera* cam = renderer_->GetActiveCamera();
  cam->SetPosition(home_.position);
  cam->SetFocalPoint(home_.focal_point);
  cam->SetViewUp(home_.view_up);
  cam->SetViewAngle(home_.view_angle_deg);
  cam->OrthogonalizeViewUp();
  renderer_->ResetCameraClippingRange();
  render();
}

lap::Status VtkView::save_png(const QString& file) {
  render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(render_window_);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.toLocal8Bit().constData());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0) {
    return lap::diagnostic("could not write " + file.toStdString());
  }
  return {};
}

void VtkView::paintEvent(QPaintEvent*) { render(); }
void VtkView::resizeEvent(QResizeEvent*) { render(); }
void VtkView::showEvent(QShowEvent*) { render(); }

void VtkView::scope(ScopeMove move, double a, double b) {
  emit scope_command({move, a, b});
  render();
}

void VtkView::mousePressEvent(QMouseEvent* e) {
  last_mouse_ = e->position().toPoint();
  buttons_ = e->buttons();
}

void VtkView::mouseMoveEvent(QMouseEvent* e) {
  const QPoint p = e->position().toPoint();
  const QPoint d = p - last_mouse_;
  last_mouse_ = p;
  const bool shift = (e->modifiers() & Qt::ShiftModifier) != 0;
  const bool ctrl = (e->modifiers() & Qt::ControlModifier) != 0;
  constexpr double kRadPerPixel = 0.0025;  // the scope pivots 0.14 degrees per pixel
  if (ctrl && ((buttons_ & Qt::MiddleButton) || ((buttons_ & Qt::LeftButton) && shift))) {
    // The tool turns about its shaft with the horizontal motion, as the scope does without Ctrl.
    emit tool_nudged(hardware::mouse_roll_nudge(d.x()));
  } else if ((buttons_ & Qt::LeftButton) && ctrl) {
    // The tool's handle follows the mouse in the view's plane.
    double up[3];
    double dir[3];
    vtkCamera* cam = renderer_->GetActiveCamera();
    cam->GetViewUp(up);
    cam->GetDirectionOfProjection(dir);
    const Eigen::Vector3d up_W = Eigen::Vector3d(up[0], up[1], up[2]).normalized();
    const Eigen::Vector3d right_W =
        Eigen::Vector3d(dir[0], dir[1], dir[2]).cross(up_W).normalized();
    emit tool_nudged(hardware::mouse_drag_nudge(d.x(), d.y(), right_W, up_W));
  } else if ((buttons_ & Qt::RightButton) && ctrl) {
    emit tool_nudged(hardware::mouse_jaws_nudge(d.y()));
  } else if ((buttons_ & Qt::MiddleButton) || ((buttons_ & Qt::LeftButton) && shift)) {
    scope(ScopeMove::kRoll, 2.0 * kRadPerPixel * d.x());
  } else if (buttons_ & Qt::LeftButton) {
    // Drag the picture: the view turns the other way, as a grabbed scene would move.
    scope(ScopeMove::kPivot, -kRadPerPixel * d.x(), kRadPerPixel * d.y());
  } else if (buttons_ & Qt::RightButton) {
    scope(ScopeMove::kInsert, -0.0005 * d.y());  // up: in, 0.5 mm per pixel
  }
}

void VtkView::mouseReleaseEvent(QMouseEvent* e) { buttons_ = e->buttons(); }

void VtkView::wheelEvent(QWheelEvent* e) {
  const double notches = e->angleDelta().y() / 120.0;
  if ((e->modifiers() & Qt::ControlModifier) != 0) {
    // Along the line of sight, away from the viewer for a forward turn. With Shift held some
    // systems report a vertical wheel as horizontal (forward as +x): then that axis counts, and
    // only then (a sideways tilt or swipe without Shift does not move the tool).
    const bool fine = (e->modifiers() & Qt::ShiftModifier) != 0;
    const QPoint a = e->angleDelta();
    const double turned = (a.y() != 0 || !fine ? a.y() : a.x()) / 120.0;
    double dir[3];
    renderer_->GetActiveCamera()->GetDirectionOfProjection(dir);
    emit tool_nudged(hardware::mouse_wheel_nudge(
        turned, Eigen::Vector3d(dir[0], dir[1], dir[2]).normalized(), fine));
    return;
  }
  scope(ScopeMove::kZoom, std::pow(1.1, notches));
}

void VtkView::keyPressEvent(QKeyEvent* e) {
  constexpr double kPivot = 2.0 * M_PI / 180.0;  // per press
  constexpr double kTurn = 10.0 * M_PI / 180.0;
  constexpr double kSlide = 0.005;  // m
  switch (e->key()) {
    case Qt::Key_Left:
      scope(ScopeMove::kPivot, -kPivot, 0.0);
      break;
    case Qt::Key_Right:
      scope(ScopeMove::kPivot, kPivot, 0.0);
      break;
    case Qt::Key_Up:
      scope(ScopeMove::kPivot, 0.0, kPivot);
      break;
    case Qt::Key_Down:
      scope(ScopeMove::kPivot, 0.0, -kPivot);
      break;
    case Qt::Key_Plus:
    case Qt::Key_Equal:
      scope(ScopeMove::kZoom, 1.1);
      break;
    case Qt::Key_Minus:
      scope(ScopeMove::kZoom, 1.0 / 1.1);
      break;
    case Qt::Key_W:
      scope(ScopeMove::kInsert, kSlide);
      break;
    case Qt::Key_S:
      scope(ScopeMove::kInsert, -kSlide);
      break;
    case Qt::Key_A:
      scope(ScopeMove::kRoll, -kTurn);
      break;
    case Qt::Key_D:
      scope(ScopeMove::kRoll, kTurn);
      break;
    case Qt::Key_Q:
      scope(ScopeMove::kHorizon, kTurn);
      break;
    case Qt::Key_E:
      scope(ScopeMove::kHorizon, -kTurn);
      break;
    case Qt::Key_C:
      scope(ScopeMove::kToggleAssistant, 0.0);
      break;
    case Qt::Key_R:
      reset_camera();
      break;
    default:
      QWidget::keyPressEvent(e);
  }
}

}  // namespace lap::app
