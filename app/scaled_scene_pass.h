#pragma once
/// \file
/// A VTK render pass that draws the 3D scene into an off-screen buffer a fraction of the window's
/// size, stretches it onto the window with bilinear filtering, and then draws the 2D overlays
/// (the heads-up display, the vignette) at the window's own resolution, so text stays sharp.
/// It is what keeps a software renderer (Mesa's llvmpipe, no GPU) at a usable frame rate: its
/// cost is mostly per pixel, and 0.7 of each side is under half the pixels (render_quality.h,
/// docs/benchmarks.md). At scale 1 it is not installed (VtkView::set_scene_scale): the
/// renderer's own passes run.

#include <vtkRenderPass.h>
#include <vtkSmartPointer.h>

#include <array>
#include <vector>

class vtkOpenGLFramebufferObject;
class vtkOpenGLRenderWindow;
class vtkRenderer;
class vtkProp;

namespace lap::app {

class ScaledScenePass : public vtkRenderPass {
 public:
  /// (VTK's reference-counted objects are made by New and freed by Delete, as vtkNew and
  /// vtkSmartPointer do.)
  static ScaledScenePass* New();

  /// The off-screen buffer's side as a fraction of the window's, (0, 1].
  void set_scale(double scale) { scale_ = scale; }
  /// Whether the driver refused the off-screen buffer: the scene is then drawn at the window's
  /// size, whatever the scale.
  [[nodiscard]] bool unavailable() const { return unavailable_; }

  void Render(const vtkRenderState* s) override;
  /// Frees the off-screen buffer (made again, at the right size, by the next Render).
  void ReleaseGraphicsResources(vtkWindow* w) override;

 protected:
  ScaledScenePass();
  ~ScaledScenePass() override;

 private:
  ScaledScenePass(const ScaledScenePass&) = delete;
  void operator=(const ScaledScenePass&) = delete;

  // The 3D props drawn into the off-screen buffer of w x h pixels; false (and never tried again)
  // when the driver cannot make one.
  bool draw_scene_off_screen(vtkRenderer* ren, vtkOpenGLRenderWindow* window, int w, int h);

  double scale_ = 1.0;
  bool unavailable_ = false;
  std::array<int, 2> buffer_size_{0, 0};
  vtkSmartPointer<vtkRenderPass> scene_;    // camera, lights, opaque and translucent geometry
  vtkSmartPointer<vtkRenderPass> overlay_;  // the 2D actors
  vtkOpenGLFramebufferObject* buffer_ = nullptr;
  std::vector<vtkProp*> props_3d_;
  std::vector<vtkProp*> props_2d_;
};

}  // namespace lap::app
