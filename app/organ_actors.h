#pragma once
/// \file
/// The organs as the graphics loop draws them: each organ's surface as the session has it (the
/// duct: its shell), with its colour texture where the scene has one (a glTF's base colour
/// image on its texture coordinates, uploaded once; an organ without one gets a mottling of its
/// colour on coordinates wrapped round it) and a wet look — a tight, bright specular
/// highlight from the scope's light, as serosa under a film of fluid gives. Deformed in place
/// from each new model snapshot (§6.5: the deformed surface is the one drawn): only the moved
/// vertices' points and the normals the dent turned are written into the float buffers.

#include <vtkActor.h>
#include <vtkFloatArray.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <memory>
#include <vector>

#include "haptics/mesh_database.h"
#include "haptics/triangle_mesh.h"
#include "sim/runtime/deformed_surface.h"
#include "sim/runtime/session.h"
#include "sim/setup/gltf_albedo.h"

namespace lap::app {

/// How one organ is drawn.
struct OrganLook {
  Eigen::Vector3d colour = Eigen::Vector3d(0.8, 0.5, 0.45);  ///< without a texture
  std::shared_ptr<const haptics::RgbImage> albedo;           ///< its colour texture, or null
};

class OrganActors {
 public:
  /// One actor per surface (at rest), added to `renderer`.
  void add(vtkRenderer* renderer, const std::vector<const haptics::TriangleMesh*>& surfaces,
           const std::vector<OrganLook>& looks);
  /// To the snapshot's deformations (nothing when its step was already drawn).
  void update(const sim::ModelSnapshot& model);
  /// Each organ's texture filtered with mipmaps (trilinear) or bilinearly (the renderer's fast
  /// profile: render_quality.h). The texture is replaced by a new one on the same image: an
  /// uploaded texture told to drop its mipmaps was measured re-uploading on every frame
  /// (VTK 9.1, llvmpipe: 10 frames/s instead of 24).
  void set_texture_mipmaps(bool on);

  [[nodiscard]] size_t size() const { return organs_.size(); }
  /// The polygons drawn for organ o (points and normals as last updated).
  [[nodiscard]] vtkPolyData* poly(size_t o) const { return organs_[o].poly; }
  [[nodiscard]] vtkActor* actor(size_t o) const { return organs_[o].actor; }
  /// Whether organ o is drawn with its own colour texture (else a mottling of its colour).
  [[nodiscard]] bool textured(size_t o) const { return organs_[o].textured; }

 private:
  struct Organ {
    vtkSmartPointer<vtkActor> actor;
    vtkSmartPointer<vtkPolyData> poly;
    vtkSmartPointer<vtkFloatArray> normals;
    std::unique_ptr<haptics::MeshDatabase> db;  // the drawn surface's normals, updated locally
    std::unique_ptr<haptics::MeshUpdateScratch> scratch;
    sim::DeformedSurface surface{{}};
    bool textured = false;
  };
  std::vector<Organ> organs_;
  int64_t steps_ = -1;  ///< the model step drawn
};

/// The wet tissue's surface look on an actor's property (shared by the organs and the tests).
void set_wet_look(vtkActor* actor);

}  // namespace lap::app
