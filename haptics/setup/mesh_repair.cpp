#include "haptics/setup/mesh_repair.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "haptics/setup/mesh_topology.h"

namespace lap::haptics {
namespace {

struct CellHash {
  size_t operator()(const std::array<int64_t, 3>& c) const {
    uint64_t h = 0x9E3779B97F4A7C15ULL;
    for (int64_t v : c) h = (h ^ static_cast<uint64_t>(v)) * 0xBF58476D1CE4E5B9ULL;
    return static_cast<size_t>(h ^ (h >> 31U));
  }
};

// Keeps only triangles[t] with keep[t], compacting in place.
int32_t filter_triangles(TriangleMesh& mesh, const std::vector<bool>& keep) {
  size_t out = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (keep[t]) mesh.triangles[out++] = mesh.triangles[t];
  }
  const auto removed = static_cast<int32_t>(mesh.triangles.size() - out);
  mesh.triangles.resize(out);
  return removed;
}

std::vector<bool> all_usable(const TriangleMesh& mesh) {
  return std::vector<bool>(mesh.triangles.size(), true);
}

// Closes boundary loops of at most max_edges edges with a fan around the loop's centroid.
void close_holes(TriangleMesh& mesh, int32_t max_edges, MeshRepairReport& report) {
  const EdgeMap edges = build_edge_map(mesh, all_usable(mesh));
  // Hole half-edges run opposite to the single triangle's edge.
  std::unordered_map<int32_t, std::vector<int32_t>> next;
  size_t boundary = 0;
  for (const auto& [key, uses] : edges) {
    if (uses.size() != 1) continue;
    const Triangle& tri = mesh.triangles[uses[0].triangle];
    for (int k = 0; k < 3; ++k) {
      const int32_t a = tri[k];
      const int32_t b = tri[(k + 1) % 3];
      if (pack_edge(a, b) == key) {
        next[b].push_back(a);
        ++boundary;
      }
    }
  }
  if (boundary == 0) return;
  std::unordered_set<uint64_t> used;
  std::vector<int32_t> starts;
  starts.reserve(next.size());
  for (const auto& [v, outs] : next) starts.push_back(v);
  std::sort(starts.begin(), starts.end());  // deterministic result
  for (int32_t start : starts) {
    for (int32_t first : next[start]) {
      if (used.count(pack_edge(start, first)) != 0) continue;
      std::vector<int32_t> loop{start};
      int32_t cur = first;
      int32_t prev = start;
      used.insert(pack_edge(start, first));
      bool ok = true;
      while (cur != start) {
        loop.push_back(cur);
        const auto it = next.find(cur);
        if (it == next.end() || loop.size() > boundary) {
          ok = false;
          break;
        }
        int32_t chosen = -1;
        for (int32_t cand : it->second) {
          if (used.count(pack_edge(cur, cand)) == 0) {
            chosen = cand;
            break;
          }
        }
        if (chosen < 0) {
          ok = false;
          break;
        }
        used.insert(pack_edge(cur, chosen));
        prev = cur;
        cur = chosen;
      }
      (void)prev;
      if (!ok || loop.size() < 3) {
        ++report.holes_left_open;
        continue;
      }
      if (static_cast<int32_t>(loop.size()) > max_edges) {
        ++report.holes_left_open;
        continue;
      }
      if (loop.size() == 3) {
        mesh.triangles.push_back({loop[0], loop[1], loop[2]});
        report.added_triangles += 1;
      } else {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int32_t v : loop) c += mesh.positions[v];
        c /= static_cast<double>(loop.size());
        const int32_t ci = mesh.vertex_count();
        mesh.positions.push_back(c);
        for (size_t i = 0; i < loop.size(); ++i) {
          mesh.triangles.push_back({loop[i], loop[(i + 1) % loop.size()], ci});
        }
        report.added_triangles += static_cast<int32_t>(loop.size());
      }
      ++report.closed_holes;
    }
  }
}

// Gives each extra fan around a pinched vertex its own copy of the vertex.
int32_t split_non_manifold_vertices(TriangleMesh& mesh) {
  const std::vector<bool> usable = all_usable(mesh);
  const EdgeMap edges = build_edge_map(mesh, usable);
  const std::vector<int32_t> pinched = find_non_manifold_vertices(mesh, usable, edges);
  int32_t added = 0;
  for (int32_t v : pinched) {
    std::vector<int32_t> around;
    for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      if (tri[0] == v || tri[1] == v || tri[2] == v) around.push_back(t);
    }
    DisjointSets sets(around.size());
    for (size_t i = 0; i < around.size(); ++i) {
      for (size_t j = i + 1; j < around.size(); ++j) {
        for (int32_t w : mesh.triangles[around[i]]) {
          if (w == v) continue;
          const Triangle& o = mesh.triangles[around[j]];
          if (std::find(o.begin(), o.end(), w) == o.end()) continue;
          const auto it = edges.find(pack_edge(v, w));
          if (it != edges.end() && it->second.size() == 2) {
            sets.unite(static_cast<int32_t>(i), static_cast<int32_t>(j));
          }
        }
      }
    }
    std::map<int32_t, int32_t> copy_of_root;
    for (size_t i = 0; i < around.size(); ++i) {
      const int32_t root = sets.find(static_cast<int32_t>(i));
      if (root == sets.find(0)) continue;  // the first fan keeps the original vertex
      auto [it, inserted] = copy_of_root.emplace(root, -1);
      if (inserted) {
        it->second = mesh.vertex_count();
        mesh.positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) mesh.normals.push_back(mesh.normals[v]);
        if (!mesh.uvs.empty()) mesh.uvs.push_back(mesh.uvs[v]);
        ++added;
      }
      for (int32_t& x : mesh.triangles[around[i]]) {
        if (x == v) x = it->second;
      }
    }
  }
  return added;
}

}  // namespace

int32_t weld_vertices(TriangleMesh& mesh, double tolerance) {
  const int32_t n = mesh.vertex_count();
  std::vector<int32_t> remap(n, -1);
  std::vector<int32_t> order;  // representatives in first-seen order
  if (tolerance > 0.0) {
    // Grid with cells of the tolerance: a match lies in the 27 surrounding cells.
    std::unordered_map<std::array<int64_t, 3>, std::vector<int32_t>, CellHash> grid;
    const double inv = 1.0 / tolerance;
    const double tol2 = tolerance * tolerance;
    for (int32_t v = 0; v < n; ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      if (!p.allFinite()) {
        remap[v] = static_cast<int32_t>(order.size());
        order.push_back(v);
        continue;
      }
      const std::array<int64_t, 3> c = {static_cast<int64_t>(std::floor(p.x() * inv)),
                                        static_cast<int64_t>(std::floor(p.y() * inv)),
                                        static_cast<int64_t>(std::floor(p.z() * inv))};
      int32_t found = -1;
      for (int dx = -1; dx <= 1 && found < 0; ++dx) {
        for (int dy = -1; dy <= 1 && found < 0; ++dy) {
          for (int dz = -1; dz <= 1 && found < 0; ++dz) {
            const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
            if (it == grid.end()) continue;
            for (int32_t r : it->second) {
              if ((mesh.positions[r] - p).squaredNorm() <= tol2) {
                found = r;
                break;
              }
            }
          }
        }
      }
      if (found >= 0) {
        remap[v] = remap[found];
      } else {
        remap[v] = static_cast<int32_t>(order.size());
        order.push_back(v);
        grid[c].push_back(v);
      }
    }
  } else {
    struct ExactHash {
      size_t operator()(const std::array<double, 3>& p) const {
        size_t h = 0;
        for (double d : p) h = h * 1000003U ^ std::hash<double>()(d == 0.0 ? 0.0 : d);
        return h;
      }
    };
    std::unordered_map<std::array<double, 3>, int32_t, ExactHash> seen;
    seen.reserve(n);
    for (int32_t v = 0; v < n; ++v) {
      const Eigen::Vector3d& p = mesh.positions[v];
      // NaN never equals itself, so non-finite vertices stay separate (validation reports them).
      const auto [it, inserted] = seen.emplace(std::array<double, 3>{p.x(), p.y(), p.z()},
                                               static_cast<int32_t>(order.size()));
      if (inserted || !p.allFinite()) {
        remap[v] = static_cast<int32_t>(order.size());
        order.push_back(v);
      } else {
        remap[v] = it->second;
      }
    }
  }
  // Drop unreferenced vertices as part of compaction, except that invalid indices are left for
  // validation to report.
  std::vector<bool> referenced(order.size(), false);
  for (const Triangle& t : mesh.triangles) {
    for (int32_t v : t) {
      if (v >= 0 && v < n) referenced[remap[v]] = true;
    }
  }
  std::vector<int32_t> final_index(order.size(), -1);
  TriangleMesh out;
  const bool has_n = mesh.normals.size() == mesh.positions.size();
  const bool has_uv = mesh.uvs.size() == mesh.positions.size();
  for (size_t r = 0; r < order.size(); ++r) {
    if (!referenced[r]) continue;
    final_index[r] = out.vertex_count();
    out.positions.push_back(mesh.positions[order[r]]);
    if (has_n) out.normals.push_back(mesh.normals[order[r]]);
    if (has_uv) out.uvs.push_back(mesh.uvs[order[r]]);
  }
  for (Triangle& t : mesh.triangles) {
    for (int32_t& v : t) {
      if (v >= 0 && v < n) v = final_index[remap[v]];
    }
  }
  const int32_t removed = n - out.vertex_count();
  mesh.positions = std::move(out.positions);
  mesh.normals = std::move(out.normals);
  mesh.uvs = std::move(out.uvs);
  return removed;
}

int32_t remove_unreferenced_vertices(TriangleMesh& mesh) {
  const int32_t n = mesh.vertex_count();
  std::vector<int32_t> index(n, -1);
  for (const Triangle& t : mesh.triangles) {
    for (int32_t v : t) {
      if (v >= 0 && v < n) index[v] = 0;
    }
  }
  int32_t next = 0;
  const bool has_n = mesh.normals.size() == mesh.positions.size();
  const bool has_uv = mesh.uvs.size() == mesh.positions.size();
  for (int32_t v = 0; v < n; ++v) {
    if (index[v] < 0) continue;
    index[v] = next;
    mesh.positions[next] = mesh.positions[v];
    if (has_n) mesh.normals[next] = mesh.normals[v];
    if (has_uv) mesh.uvs[next] = mesh.uvs[v];
    ++next;
  }
  mesh.positions.resize(next);
  if (has_n) mesh.normals.resize(next);
  if (has_uv) mesh.uvs.resize(next);
  for (Triangle& t : mesh.triangles) {
    for (int32_t& v : t) {
      if (v >= 0 && v < n) v = index[v];
    }
  }
  return n - next;
}

std::string MeshRepairReport::summary() const {
  std::ostringstream s;
  s << "removed " << removed_invalid << " invalid, " << removed_degenerate << " degenerate, "
    << removed_duplicates << " duplicate triangles; welded " << welded_vertices
    << " vertices; dropped " << removed_fragments << " fragments (" << removed_fragment_triangles
    << " triangles); removed " << removed_non_manifold_triangles
    << " triangles on non-manifold edges; split " << split_vertices << " vertices; flipped "
    << flipped_triangles << " triangles and " << flipped_components << " components; closed "
    << closed_holes << " holes with " << added_triangles << " triangles";
  if (holes_left_open > 0) s << "; " << holes_left_open << " holes too large to close";
  return s.str();
}

MeshRepairReport repair_mesh(TriangleMesh& mesh, const MeshRepairSettings& settings) {
  MeshRepairReport report;
  // 1. Triangles that cannot be part of any surface.
  {
    std::vector<bool> keep(mesh.triangles.size(), true);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int32_t v : mesh.triangles[t]) {
        if (v < 0 || v >= mesh.vertex_count() || !mesh.positions[v].allFinite()) keep[t] = false;
      }
    }
    report.removed_invalid = filter_triangles(mesh, keep);
  }
  // 2. Weld.
  report.welded_vertices = weld_vertices(mesh, settings.weld_tolerance);
  // 3. Degenerate and duplicate triangles.
  if (settings.drop_degenerate) {
    std::vector<bool> keep(mesh.triangles.size(), true);
    std::unordered_set<std::array<int32_t, 3>, TripleHash> seen;
    for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
          !(0.5 * mesh.triangle_cross(t).norm() > settings.validation.degenerate_area)) {
        keep[t] = false;
        ++report.removed_degenerate;
      } else if (!seen.insert(sorted_triangle(tri)).second) {
        keep[t] = false;
        ++report.removed_duplicates;
      }
    }
    filter_triangles(mesh, keep);
  }
  // 4. Debris.
  if (settings.drop_fragments) {
    const MeshDiagnostics d = validate_mesh(mesh, settings.validation);
    std::vector<bool> fragment(d.part_count, false);
    for (int32_t p : d.sliver_fragments) fragment[p] = true;
    std::vector<bool> keep(mesh.triangles.size(), true);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      const int32_t c = d.triangle_part[t];
      if (c >= 0 && fragment[c]) keep[t] = false;
    }
    report.removed_fragments = static_cast<int32_t>(d.sliver_fragments.size());
    report.removed_fragment_triangles = filter_triangles(mesh, keep);
  }
  // 5. Non-manifold edges: keep the two triangles of the largest components on each such edge.
  if (settings.resolve_non_manifold) {
    const std::vector<bool> usable = all_usable(mesh);
    const EdgeMap edges = build_edge_map(mesh, usable);
    const Components comps = connected_components(mesh, usable, edges);
    std::vector<bool> keep(mesh.triangles.size(), true);
    for (const auto& [key, uses] : edges) {
      if (uses.size() <= 2) continue;
      std::vector<EdgeUse> sorted = uses;
      std::stable_sort(sorted.begin(), sorted.end(), [&](const EdgeUse& a, const EdgeUse& b) {
        return comps.stats[comps.of_triangle[a.triangle]].triangles >
               comps.stats[comps.of_triangle[b.triangle]].triangles;
      });
      for (size_t i = 2; i < sorted.size(); ++i) keep[sorted[i].triangle] = false;
    }
    report.removed_non_manifold_triangles = filter_triangles(mesh, keep);
    report.split_vertices = split_non_manifold_vertices(mesh);
  }
  // 6. Consistent winding within each component.
  if (settings.fix_orientation) {
    const std::vector<bool> usable = all_usable(mesh);
    const EdgeMap edges = build_edge_map(mesh, usable);
    const Components comps = connected_components(mesh, usable, edges);
    const OrientationSolve solve = solve_orientation(mesh, usable, edges, comps);
    for (int32_t t : solve.minority_triangles)
      std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    report.flipped_triangles = static_cast<int32_t>(solve.minority_triangles.size());
  }
  // 7. Holes, then 8. outward normals (volume is only meaningful once closed).
  if (settings.max_hole_edges >= 3) close_holes(mesh, settings.max_hole_edges, report);
  if (settings.fix_orientation) {
    const std::vector<bool> usable = all_usable(mesh);
    const EdgeMap edges = build_edge_map(mesh, usable);
    const Components comps = connected_components(mesh, usable, edges);
    std::vector<bool> flip(comps.count, false);
    for (int32_t c = 0; c < comps.count; ++c) {
      if (comps.stats[c].signed_volume < 0.0) {
        flip[c] = true;
        ++report.flipped_components;
      }
    }
    for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
      if (flip[comps.of_triangle[t]]) std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
    }
  }
  remove_unreferenced_vertices(mesh);
  mesh.compute_vertex_normals();
  return report;
}

}  // namespace lap::haptics
