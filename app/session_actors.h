#pragma once
/// \file
/// What the graphics loop draws of the running session, all updated in place from the newest
/// snapshots: the organs as the modelling loop deforms them, textured and wet (organ_actors.h);
/// the two instruments as 3D models at their proxies (instrument_actors.h); the catheter as a
/// tube of its real diameter along its particles (catheter_tube.h).

#include <vtkActor.h>
#include <vtkFloatArray.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <array>
#include <memory>
#include <vector>

#include "app/catheter_tube.h"
#include "app/instrument_actors.h"
#include "app/organ_actors.h"
#include "sim/report/replay_timeline.h"
#include "sim/runtime/session.h"
#include "sim/setup/scene.h"
#include "sim/setup/session_model.h"

namespace lap::app {

/// Everything drawn, fixed when the session starts.
struct SessionDrawing {
  std::vector<const haptics::TriangleMesh*> surfaces;  ///< the session's organ surfaces at rest
  std::vector<OrganLook> looks;                        ///< one per surface
  std::array<InstrumentSpec, 2> instruments{};
  int32_t catheter_points = 0;  ///< 0: no catheter
  double catheter_radius_m = 0.0;
};

/// From the scene and the session model built on it (its organ surfaces, the tools' ports and
/// gripper geometry, the catheter's model); kinds, radii, colours and textures from the scene.
[[nodiscard]] SessionDrawing session_drawing(const sim::Scene& scene,
                                             const sim::SessionModel& model);

/// From what a review's replay kept of the scene (sim/report/replay_timeline.h), the same.
[[nodiscard]] SessionDrawing replay_drawing(const sim::ReplayScene& scene);

class SessionActors {
 public:
  /// Adds every actor to `renderer` (the surfaces must outlive this).
  void add(vtkRenderer* renderer, const SessionDrawing& drawing);
  /// Moves them to the snapshots' state.
  void update(const sim::HapticSnapshot& haptic, const sim::ModelSnapshot& model);

  [[nodiscard]] const OrganActors& organs() const { return organs_; }
  /// The organs' textures filtered with mipmaps or not (OrganActors::set_texture_mipmaps).
  void set_texture_mipmaps(bool on) { organs_.set_texture_mipmaps(on); }
  /// The polygons drawn for organ o (points and normals as last updated).
  [[nodiscard]] vtkPolyData* organ_poly(size_t o) const { return organs_.poly(o); }
  [[nodiscard]] const InstrumentActors& instrument(int tool) const {
    return instruments_[static_cast<size_t>(tool)];
  }
  /// The catheter's tube (null without a catheter).
  [[nodiscard]] vtkPolyData* catheter_poly() const { return catheter_poly_; }
  [[nodiscard]] vtkActor* catheter_actor() const { return catheter_actor_; }

 private:
  OrganActors organs_;
  std::array<InstrumentActors, 2> instruments_;
  std::unique_ptr<CatheterTube> tube_;
  double catheter_radius_m_ = 0.0;
  vtkSmartPointer<vtkPolyData> catheter_poly_;
  vtkSmartPointer<vtkFloatArray> catheter_normals_;
  vtkSmartPointer<vtkActor> catheter_actor_;
};

}  // namespace lap::app
