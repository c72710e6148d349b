#pragma once
/// \file
/// Opt-in repair of the defects mesh_validation reports, turning a defective scan into a
/// closed, consistently oriented, outward-facing mesh where that is possible.

#include <cstdint>
#include <string>
#include <vector>

#include "haptics/setup/mesh_validation.h"
#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// Merges vertices closer than tolerance [m] (0: exact duplicates), compacts the vertex array and
/// drops unreferenced vertices. Returns how many vertices were removed.
int32_t weld_vertices(TriangleMesh& mesh, double tolerance);

/// Drops vertices no triangle uses and compacts the arrays; returns how many were dropped.
int32_t remove_unreferenced_vertices(TriangleMesh& mesh);

/// What repair may do. Each step is reported in RepairReport.
struct MeshRepairSettings {
  double weld_tolerance = 0.0;        ///< [m]; 0 welds exact duplicates only
  bool drop_degenerate = true;        ///< collapsed triangles and exact duplicates
  bool drop_fragments = true;         ///< sliver fragments per validation settings
  bool resolve_non_manifold = true;   ///< extra triangles on edges, split pinched vertices
  bool fix_orientation = true;        ///< consistent winding, then outward normals
  int32_t max_hole_edges = 64;        ///< holes with at most this many edges are closed
  MeshValidationSettings validation;  ///< thresholds shared with the diagnosis
};

/// Counts of what repair changed.
struct MeshRepairReport {
  int32_t removed_invalid = 0;  ///< triangles with bad indices or non-finite corners
  int32_t welded_vertices = 0;
  int32_t removed_degenerate = 0;
  int32_t removed_duplicates = 0;
  int32_t removed_fragment_triangles = 0;
  int32_t removed_fragments = 0;
  int32_t removed_non_manifold_triangles = 0;
  int32_t split_vertices = 0;
  int32_t flipped_triangles = 0;
  int32_t flipped_components = 0;
  int32_t closed_holes = 0;
  int32_t added_triangles = 0;
  int32_t holes_left_open = 0;  ///< holes larger than max_hole_edges
  [[nodiscard]] std::string summary() const;
};

/// Repairs mesh in place; normals are recomputed. Returns what it did.
MeshRepairReport repair_mesh(TriangleMesh& mesh, const MeshRepairSettings& settings = {});

}  // namespace lap::haptics
