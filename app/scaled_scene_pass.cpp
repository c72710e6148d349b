#include "app/scaled_scene_pass.h"

#include <vtkActor2D.h>
#include <vtkCameraPass.h>
#include <vtkLightsPass.h>
#include <vtkOpaquePass.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkOverlayPass.h>
#include <vtkProp.h>
#include <vtkRenderPassCollection.h>
#include <vtkRenderState.h>
#include <vtkRenderer.h>
#include <vtkSequencePass.h>
#include <vtkTranslucentPass.h>
#include <vtk_glew.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string_view>

namespace lap::app {

ScaledScenePass* ScaledScenePass::New() {
  auto* pass = new ScaledScenePass;
  pass->InitializeObjectBase();
  return pass;
}

ScaledScenePass::ScaledScenePass() {
  vtkNew<vtkSequencePass> steps;
  vtkNew<vtkRenderPassCollection> passes;
  vtkNew<vtkLightsPass> lights;
  vtkNew<vtkOpaquePass> opaque;
  vtkNew<vtkTranslucentPass> translucent;
  passes->AddItem(lights);
  passes->AddItem(opaque);
  passes->AddItem(translucent);
  steps->SetPasses(passes);
  auto camera = vtkSmartPointer<vtkCameraPass>::New();
  camera->SetDelegatePass(steps);
  scene_ = camera;
  // The 2D actors go through the opaque and translucent passes too: a text actor rasterizes its
  // text there, and draws it in the overlay pass.
  auto overlay = vtkSmartPointer<vtkSequencePass>::New();
  vtkNew<vtkRenderPassCollection> overlay_passes;
  vtkNew<vtkOpaquePass> prepare;
  vtkNew<vtkTranslucentPass> prepare_translucent;
  vtkNew<vtkOverlayPass> draw;
  overlay_passes->AddItem(prepare);
  overlay_passes->AddItem(prepare_translucent);
  overlay_passes->AddItem(draw);
  overlay->SetPasses(overlay_passes);
  overlay_ = overlay;
}

ScaledScenePass::~ScaledScenePass() {
  if (buffer_ != nullptr) buffer_->Delete();
}

void ScaledScenePass::ReleaseGraphicsResources(vtkWindow* w) {
  scene_->ReleaseGraphicsResources(w);
  overlay_->ReleaseGraphicsResources(w);
  // A released buffer keeps its attachments' entries (VTK 9.1) and could not be filled again:
  // it is dropped and made anew.
  if (buffer_ != nullptr) {
    buffer_->ReleaseGraphicsResources(w);
    buffer_->Delete();
    buffer_ = nullptr;
  }
  buffer_size_ = {0, 0};
}

bool ScaledScenePass::draw_scene_off_screen(vtkRenderer* ren, vtkOpenGLRenderWindow* window, int w,
                                            int h) {
  if (unavailable_) return false;
  vtkOpenGLState* gl = window->GetState();
  if (buffer_ == nullptr) {
    buffer_ = vtkOpenGLFramebufferObject::New();
    buffer_->SetContext(window);
  }
  gl->PushFramebufferBindings();
  buffer_->Bind();
  if (buffer_size_[0] == 0) {
    // LAPTRAINER_NO_OFFSCREEN_BUFFER=1 plays a driver that gives none (the fallback's test).
    static const bool refused = [] {
      const char* v = std::getenv("LAPTRAINER_NO_OFFSCREEN_BUFFER");
      return v != nullptr && std::string_view(v) == "1";
    }();
    if (refused ||
        !buffer_->PopulateFramebuffer(w, h, /*useTextures=*/true, /*numberOfColorAttachments=*/1,
                                      VTK_UNSIGNED_CHAR, /*wantDepthAttachment=*/true,
                                      /*depthBitplanes=*/24, /*multisamples=*/0)) {
      gl->PopFramebufferBindings();
      ReleaseGraphicsResources(window);
      unavailable_ = true;  // not tried again on every frame
      std::cerr << "laptrainer: the OpenGL driver gave no off-screen buffer for the smaller "
                   "picture; the scene is drawn at the window's size\n";
      return false;
    }
  } else if (buffer_size_[0] != w || buffer_size_[1] != h) {
    buffer_->Resize(w, h);
  }
  buffer_size_ = {w, h};
  buffer_->ActivateDrawBuffer(0);
  vtkRenderState scene(ren);
  scene.SetPropArrayAndCount(props_3d_.data(), static_cast<int>(props_3d_.size()));
  scene.SetFrameBuffer(buffer_);
  scene_->Render(&scene);
  this->NumberOfRenderedProps += scene_->GetNumberOfRenderedProps();
  gl->PopFramebufferBindings();
  return true;
}

void ScaledScenePass::Render(const vtkRenderState* s) {
  this->NumberOfRenderedProps = 0;
  vtkRenderer* ren = s->GetRenderer();
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (window == nullptr) return;
  int width = 0;
  int height = 0;
  int x = 0;
  int y = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x, &y);
  if (width < 1 || height < 1) return;
  // The props split: 3D ones into the small picture, 2D ones (text, gauges) on the window.
  props_3d_.clear();
  props_2d_.clear();
  for (int i = 0; i < s->GetPropArrayCount(); ++i) {
    vtkProp* p = s->GetPropArray()[i];
    (vtkActor2D::SafeDownCast(p) != nullptr ? props_2d_ : props_3d_).push_back(p);
  }
  const int w = std::max(1, static_cast<int>(std::lround(width * scale_)));
  const int h = std::max(1, static_cast<int>(std::lround(height * scale_)));
  vtkOpenGLState* gl = window->GetState();
  if (draw_scene_off_screen(ren, window, w, h)) {
    // Stretched onto the window's viewport.
    gl->PushReadFramebufferBinding();
    buffer_->Bind(vtkOpenGLFramebufferObject::GetReadMode());
    buffer_->ActivateReadBuffer(0);
    {
      vtkOpenGLState::ScopedglEnableDisable scissor(gl, GL_SCISSOR_TEST);
      gl->vtkglDisable(GL_SCISSOR_TEST);
      gl->vtkglBlitFramebuffer(0, 0, w, h, x, y, x + width, y + height, GL_COLOR_BUFFER_BIT,
                               GL_LINEAR);
    }
    gl->PopReadFramebufferBinding();
  } else {
    // No off-screen buffer to be had: the scene at the window's size, as without this pass.
    vtkRenderState scene(ren);
    scene.SetPropArrayAndCount(props_3d_.data(), static_cast<int>(props_3d_.size()));
    scene_->Render(&scene);
    this->NumberOfRenderedProps += scene_->GetNumberOfRenderedProps();
  }

  // The overlays at full resolution, over the whole viewport (the camera pass put the viewport
  // and the scissor back as they were before it, which need not be this renderer's).
  vtkOpenGLState::ScopedglViewport viewport(gl);
  vtkOpenGLState::ScopedglScissor scissor(gl);
  vtkOpenGLState::ScopedglEnableDisable scissor_test(gl, GL_SCISSOR_TEST);
  gl->vtkglViewport(x, y, width, height);
  gl->vtkglScissor(x, y, width, height);
  gl->vtkglEnable(GL_SCISSOR_TEST);
  vtkRenderState overlay(ren);
  overlay.SetPropArrayAndCount(props_2d_.data(), static_cast<int>(props_2d_.size()));
  overlay_->Render(&overlay);
  this->NumberOfRenderedProps += overlay_->GetNumberOfRenderedProps();
}

}  // namespace lap::app
