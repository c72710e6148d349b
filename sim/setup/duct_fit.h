#pragma once
/// \file
/// Places the modal-shell duct (models/modal_shell.h, §7.7(2)) where a scenario's duct organ is:
/// the organ's mesh (a closed tube) gives the axis (its vertices' principal direction), the
/// length (their extent along it) and the outer diameter (their mean distance from the axis away
/// from the caps). The duct's frame D has z along the axis from its first end; its membrane line
/// (local −y) is put on the side facing world down (−y, docs/architecture.md), where the duct lies
/// on the tissue under it.

#include <Eigen/Geometry>

#include "core/result.h"
#include "haptics/triangle_mesh.h"
#include "models/modal_shell.h"

namespace lap::sim {

struct DuctFit {
  models::DuctSettings duct;
  Eigen::Isometry3d pose_WD = Eigen::Isometry3d::Identity();
};

/// The duct's settings and pose, or why the mesh is not tube-like (too few vertices, no length,
/// or a wall too thin for the duct's wall thickness).
[[nodiscard]] Result<DuctFit> fit_duct(const haptics::TriangleMesh& tube, double wall_thickness_m);

}  // namespace lap::sim
