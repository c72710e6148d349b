#pragma once
/// \file
/// Edge incidence, connected components and orientation propagation over an indexed triangle
/// mesh that may be non-manifold. Shared by validation and repair (setup code, not the step).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// One triangle's use of an undirected edge: forward when the triangle runs from the smaller to
/// the larger vertex index.
struct EdgeUse {
  int32_t triangle;
  bool forward;
};

/// Undirected edge (packed smaller << 32 | larger) to the triangles that use it.
using EdgeMap = std::unordered_map<uint64_t, std::vector<EdgeUse>>;

[[nodiscard]] inline uint64_t pack_edge(int32_t a, int32_t b) {
  const auto lo = static_cast<uint32_t>(a < b ? a : b);
  const auto hi = static_cast<uint32_t>(a < b ? b : a);
  return (static_cast<uint64_t>(lo) << 32U) | hi;
}
[[nodiscard]] inline std::array<int32_t, 2> unpack_edge(uint64_t key) {
  return {static_cast<int32_t>(key >> 32U), static_cast<int32_t>(key & 0xffffffffU)};
}
/// A triangle's vertex set in ascending order (for duplicate detection).
[[nodiscard]] std::array<int32_t, 3> sorted_triangle(const Triangle& t);
/// Hash of a vertex triple, for unordered containers keyed by sorted_triangle().
struct TripleHash {
  size_t operator()(const std::array<int32_t, 3>& s) const;
};

/// Edge incidence of the triangles marked usable.
[[nodiscard]] EdgeMap build_edge_map(const TriangleMesh& mesh, const std::vector<bool>& usable);

struct ComponentStats {
  int32_t triangles = 0;
  double area = 0.0;           // [m^2]
  double signed_volume = 0.0;  // [m^3], meaningful for closed oriented components
};

/// Edge-connected components of the usable triangles (-1 for unusable ones).
struct Components {
  int32_t count = 0;
  std::vector<int32_t> of_triangle;
  std::vector<ComponentStats> stats;
};
[[nodiscard]] Components connected_components(const TriangleMesh& mesh,
                                              const std::vector<bool>& usable,
                                              const EdgeMap& edges);

/// A 2-colouring of triangles across two-triangle edges so that neighbours agree in orientation.
struct OrientationSolve {
  std::vector<bool> flip;                   ///< flip this triangle to agree with its component
  std::vector<int32_t> minority_triangles;  ///< per component, the smaller colour class
  int32_t non_orientable_components = 0;    ///< Moebius-like: no consistent colouring exists
};
[[nodiscard]] OrientationSolve solve_orientation(const TriangleMesh& mesh,
                                                 const std::vector<bool>& usable,
                                                 const EdgeMap& edges, const Components& comps);

/// Vertices whose usable incident triangles form more than one fan (joined through edges that
/// exactly two triangles share).
[[nodiscard]] std::vector<int32_t> find_non_manifold_vertices(const TriangleMesh& mesh,
                                                              const std::vector<bool>& usable,
                                                              const EdgeMap& edges);

/// Minimal union-find with path halving.
class DisjointSets {
 public:
  explicit DisjointSets(size_t n);
  int32_t find(int32_t x);
  void unite(int32_t a, int32_t b);

 private:
  std::vector<int32_t> parent_;
};

}  // namespace lap::haptics
