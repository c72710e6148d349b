#pragma once
/// \file
/// The ductotomy (thesis §7.4, Figure 7-18): which faces of the duct's wall (its triangulated
/// modal shell) the scenario's incision opens. The catheter's contacts treat those faces as a
/// hole with a rim (models/catheter_contacts.h), so its tip can pass through the wall there and
/// nowhere else. The wall's mesh itself is kept whole: the shell's modes, the tools' proxies and
/// the graphics keep their surface (its vertices are the shell's nodes, one for one).

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/result.h"
#include "haptics/triangle_mesh.h"
#include "models/modal_shell.h"
#include "sim/setup/scenario.h"

namespace lap::sim {

/// Per face of `wall_W` (the shell triangulated, world frame), 1 where the incision opens it: a
/// face whose centroid lies in the ellipse of `incision` on the wall (its length along the
/// duct's axis, its width around it as arc length on the mid-surface). Fails, with what was
/// expected, when the centre is not on the wall (further than the wall's outer radius from its
/// mid-surface, or beyond the duct's ends) or when the ellipse opens no face (smaller than the
/// wall's mesh).
[[nodiscard]] Result<std::vector<uint8_t>> incision_faces(const haptics::TriangleMesh& wall_W,
                                                          const models::DuctSettings& duct,
                                                          const Eigen::Isometry3d& pose_WD,
                                                          const IncisionSpec& incision);

}  // namespace lap::sim
