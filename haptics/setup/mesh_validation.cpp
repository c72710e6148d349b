#include "haptics/setup/mesh_validation.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "haptics/setup/mesh_topology.h"

namespace lap::haptics {
namespace {

template <typename T>
std::string first_few(const std::vector<T>& items, size_t n = 5) {
  std::ostringstream out;
  for (size_t i = 0; i < std::min(n, items.size()); ++i) {
    if (i > 0) out << ", ";
    if constexpr (std::is_same_v<T, EdgeKey>) {
      out << items[i][0] << "-" << items[i][1];
    } else {
      out << items[i];
    }
  }
  if (items.size() > n) out << ", ...";
  return out.str();
}

}  // namespace

bool MeshDiagnostics::clean() const {
  return non_finite_vertices.empty() && invalid_index_triangles.empty() &&
         degenerate_triangles.empty() && duplicate_triangles.empty() && boundary_edges.empty() &&
         non_manifold_edges.empty() && non_manifold_vertices.empty() &&
         orientation_conflict_edges.empty() && inward_components.empty() &&
         sliver_fragments.empty();
}

std::vector<std::string> MeshDiagnostics::describe() const {
  std::vector<std::string> lines;
  auto add = [&lines](const std::string& what, const auto& items, const std::string& noun) {
    if (items.empty()) return;
    lines.push_back(std::to_string(items.size()) + " " + what + " (" + noun + " " +
                    first_few(items) + ")");
  };
  add("non-finite vertex coordinates", non_finite_vertices, "vertices");
  add("triangles with an out-of-range vertex index", invalid_index_triangles, "triangles");
  add("degenerate triangles (repeated vertex or zero area)", degenerate_triangles, "triangles");
  add("duplicate triangles", duplicate_triangles, "triangles");
  add("boundary edges: the surface is not closed", boundary_edges, "edges");
  add("non-manifold edges (shared by 3 or more triangles)", non_manifold_edges, "edges");
  add("non-manifold vertices (several separate fans of triangles)", non_manifold_vertices,
      "vertices");
  add("edges with inconsistent orientation", orientation_conflict_edges, "edges");
  add("triangles flipped against their neighbours", flipped_triangles, "triangles");
  if (!sliver_fragments.empty()) {
    lines.push_back(std::to_string(sliver_fragments.size()) +
                    " sliver fragments: small disconnected debris of " +
                    std::to_string(fragment_triangles) + " triangles in all (parts " +
                    first_few(sliver_fragments) + ")");
  }
  add("closed components with inward-facing normals", inward_components, "components");
  add("unreferenced vertices", unreferenced_vertices, "vertices");
  return lines;
}

MeshDiagnostics validate_mesh(const TriangleMesh& mesh, const MeshValidationSettings& settings) {
  MeshDiagnostics d;
  d.vertex_count = mesh.vertex_count();
  d.triangle_count = mesh.triangle_count();

  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!mesh.positions[v].allFinite()) d.non_finite_vertices.push_back(v);
  }

  // Triangles that can take part in topology: valid indices, finite, not degenerate.
  std::vector<bool> usable(mesh.triangles.size(), true);
  std::vector<bool> referenced(mesh.positions.size(), false);
  std::unordered_set<std::array<int32_t, 3>, TripleHash> seen_faces;
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (std::any_of(tri.begin(), tri.end(),
                    [&](int32_t v) { return v < 0 || v >= mesh.vertex_count(); })) {
      d.invalid_index_triangles.push_back(t);
      usable[t] = false;
      continue;
    }
    for (int32_t v : tri) referenced[v] = true;
    if (std::any_of(tri.begin(), tri.end(),
                    [&](int32_t v) { return !mesh.positions[v].allFinite(); })) {
      usable[t] = false;
      continue;
    }
    const double area = 0.5 * mesh.triangle_cross(t).norm();
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
        !(area > settings.degenerate_area)) {
      d.degenerate_triangles.push_back(t);
      usable[t] = false;
      continue;
    }
    if (!seen_faces.insert(sorted_triangle(tri)).second) {
      d.duplicate_triangles.push_back(t);
      usable[t] = false;
    }
  }
  for (int32_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!referenced[v]) d.unreferenced_vertices.push_back(v);
  }

  // Vertex-connected parts, and which of them are debris. The area is summed here, not by
  // mesh.surface_area(), which would index the out-of-range triangles (as every sum below skips
  // them, being over usable triangles only).
  double total_area = 0.0;
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    const bool in_range =
        std::none_of(mesh.triangles[t].begin(), mesh.triangles[t].end(),
                     [&](int32_t v) { return v < 0 || v >= mesh.vertex_count(); });
    if (in_range) total_area += 0.5 * mesh.triangle_cross(t).norm();
  }
  {
    DisjointSets sets(mesh.triangles.size());
    std::vector<int32_t> first_use(mesh.positions.size(), -1);
    for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
      if (!usable[t]) continue;
      for (int32_t v : mesh.triangles[t]) {
        if (first_use[v] < 0) {
          first_use[v] = t;
        } else {
          sets.unite(first_use[v], t);
        }
      }
    }
    d.triangle_part.assign(mesh.triangles.size(), -1);
    std::unordered_map<int32_t, int32_t> root_to_part;
    std::vector<int32_t> part_triangles;
    std::vector<double> part_area;
    for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
      if (!usable[t]) continue;
      const auto [it, inserted] = root_to_part.emplace(sets.find(t), d.part_count);
      if (inserted) {
        ++d.part_count;
        part_triangles.push_back(0);
        part_area.push_back(0.0);
      }
      d.triangle_part[t] = it->second;
      part_triangles[it->second] += 1;
      part_area[it->second] += 0.5 * mesh.triangle_cross(t).norm();
    }
    for (int32_t p = 0; p < d.part_count; ++p) {
      if (d.part_count > 1 && part_triangles[p] <= settings.fragment_max_triangles &&
          part_area[p] <= settings.fragment_max_area_fraction * total_area) {
        d.sliver_fragments.push_back(p);
        d.fragment_triangles += part_triangles[p];
      }
    }
  }
  std::vector<bool> in_fragment(d.part_count, false);
  for (int32_t p : d.sliver_fragments) in_fragment[p] = true;
  std::vector<bool> body = usable;
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (usable[t] && in_fragment[d.triangle_part[t]]) body[t] = false;
  }

  // Orientation over every usable triangle.
  const EdgeMap all_edges = build_edge_map(mesh, usable);
  for (const auto& [key, uses] : all_edges) {
    if (uses.size() == 2 && uses[0].forward == uses[1].forward) {
      d.orientation_conflict_edges.push_back(unpack_edge(key));
    }
  }
  std::sort(d.orientation_conflict_edges.begin(), d.orientation_conflict_edges.end());
  const Components all_comps = connected_components(mesh, usable, all_edges);
  d.component_count = all_comps.count;
  d.triangle_component = all_comps.of_triangle;
  d.flipped_triangles = solve_orientation(mesh, usable, all_edges, all_comps).minority_triangles;

  // Surface topology of the body.
  const EdgeMap edges = build_edge_map(mesh, body);
  for (const auto& [key, uses] : edges) {
    if (uses.size() == 1) d.boundary_edges.push_back(unpack_edge(key));
    if (uses.size() >= 3) d.non_manifold_edges.push_back(unpack_edge(key));
  }
  std::sort(d.boundary_edges.begin(), d.boundary_edges.end());
  std::sort(d.non_manifold_edges.begin(), d.non_manifold_edges.end());
  d.non_manifold_vertices = find_non_manifold_vertices(mesh, body, edges);

  // Inward-facing: a closed, consistently oriented body component with negative volume.
  const Components comps = connected_components(mesh, body, edges);
  std::vector<bool> comp_closed(comps.count, true);
  for (const auto& [key, uses] : edges) {
    if (uses.size() != 2) {
      for (const EdgeUse& u : uses) comp_closed[comps.of_triangle[u.triangle]] = false;
    } else if (uses[0].forward == uses[1].forward) {
      comp_closed[comps.of_triangle[uses[0].triangle]] = false;
    }
  }
  for (int32_t c = 0; c < comps.count; ++c) {
    if (comp_closed[c] && comps.stats[c].signed_volume < 0.0) d.inward_components.push_back(c);
  }
  return d;
}

}  // namespace lap::haptics
