#pragma once
/// \file
/// Diagnosis of triangle-mesh defects: what a haptic proxy needs is a closed, consistently
/// oriented 2-manifold with outward normals and no degenerate faces; this reports each way a
/// mesh falls short of that, with the offending indices.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// An undirected edge as its two vertex indices, smaller first.
using EdgeKey = std::array<int32_t, 2>;

/// Thresholds for the diagnosis; the defaults suit organ meshes in metres.
struct MeshValidationSettings {
  /// A triangle whose area is below this is degenerate [m^2]. Zero keeps sub-micrometre
  /// triangles (real scans have them): only exactly collapsed triangles count.
  double degenerate_area = 0.0;
  /// A part (triangles connected through shared vertices) with at most this many triangles and
  /// at most this fraction of the total surface area is a sliver fragment: debris left over from
  /// a scan or an export. Parts touching at a single vertex count as one fragment.
  int32_t fragment_max_triangles = 64;
  double fragment_max_area_fraction = 0.01;
};

/// Everything found wrong with a mesh. Empty lists mean no defect of that kind.
///
/// Sliver fragments are reported as one class; the surface topology (boundary edges,
/// non-manifold edges and vertices, inward components) is reported for the body, that is the
/// mesh without its fragments, because the fragments' own open edges only repeat that they are
/// debris (and repair removes them whole). Orientation conflicts are counted over all triangles.
struct MeshDiagnostics {
  int32_t vertex_count = 0;
  int32_t triangle_count = 0;
  std::vector<int32_t> non_finite_vertices;      ///< a coordinate is NaN or infinite
  std::vector<int32_t> invalid_index_triangles;  ///< an index outside the vertex array
  std::vector<int32_t> unreferenced_vertices;    ///< no triangle uses them
  std::vector<int32_t> degenerate_triangles;     ///< repeated vertex or zero area
  std::vector<int32_t> duplicate_triangles;      ///< same three vertices as an earlier triangle
  std::vector<EdgeKey> boundary_edges;           ///< used by exactly one triangle
  std::vector<EdgeKey> non_manifold_edges;       ///< used by three or more triangles
  std::vector<int32_t> non_manifold_vertices;    ///< incident triangles form several fans
  /// Interior edges whose two triangles traverse them in the same direction.
  std::vector<EdgeKey> orientation_conflict_edges;
  /// Triangles that disagree with the orientation of the majority of their component (the
  /// fewest flips that make each orientable component consistent).
  std::vector<int32_t> flipped_triangles;
  int32_t component_count = 0;              ///< edge-connected components
  std::vector<int32_t> inward_components;   ///< closed body components, negative volume
  std::vector<int32_t> triangle_component;  ///< edge-connected component of each triangle
  int32_t part_count = 0;                   ///< vertex-connected parts
  std::vector<int32_t> triangle_part;       ///< part of each triangle (-1: unusable)
  std::vector<int32_t> sliver_fragments;    ///< part ids that are debris
  int32_t fragment_triangles = 0;           ///< triangles in all sliver fragments

  /// True when the mesh is a closed, oriented, outward-facing 2-manifold with no degenerate
  /// triangles and finite coordinates: what the haptic proxies require.
  [[nodiscard]] bool clean() const;
  [[nodiscard]] bool closed() const { return boundary_edges.empty(); }
  /// One line per defect class found, each naming counts and the first few offenders.
  [[nodiscard]] std::vector<std::string> describe() const;
};

/// Diagnoses every defect class listed in MeshDiagnostics.
[[nodiscard]] MeshDiagnostics validate_mesh(const TriangleMesh& mesh,
                                            const MeshValidationSettings& settings = {});

}  // namespace lap::haptics
