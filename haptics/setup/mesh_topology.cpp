#include "haptics/setup/mesh_topology.h"

#include <algorithm>
#include <deque>
#include <numeric>

namespace lap::haptics {

DisjointSets::DisjointSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

int32_t DisjointSets::find(int32_t x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];
    x = parent_[x];
  }
  return x;
}

void DisjointSets::unite(int32_t a, int32_t b) {
  a = find(a);
  b = find(b);
  if (a != b) parent_[std::max(a, b)] = std::min(a, b);
}

std::array<int32_t, 3> sorted_triangle(const Triangle& t) {
  std::array<int32_t, 3> s = t;
  std::sort(s.begin(), s.end());
  return s;
}

size_t TripleHash::operator()(const std::array<int32_t, 3>& s) const {
  uint64_t h = 1469598103934665603ULL;
  for (int32_t v : s) {
    h ^= static_cast<uint32_t>(v);
    h *= 1099511628211ULL;
    h ^= h >> 29U;
  }
  return static_cast<size_t>(h);
}

EdgeMap build_edge_map(const TriangleMesh& mesh, const std::vector<bool>& usable) {
  EdgeMap edges;
  edges.reserve(mesh.triangles.size() * 2);
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!usable[t]) continue;
    const Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int32_t a = tri[k];
      const int32_t b = tri[(k + 1) % 3];
      edges[pack_edge(a, b)].push_back({t, a < b});
    }
  }
  return edges;
}

Components connected_components(const TriangleMesh& mesh, const std::vector<bool>& usable,
                                const EdgeMap& edges) {
  DisjointSets sets(mesh.triangles.size());
  for (const auto& [key, uses] : edges) {
    for (size_t i = 1; i < uses.size(); ++i) sets.unite(uses[0].triangle, uses[i].triangle);
  }
  Components c;
  c.of_triangle.assign(mesh.triangles.size(), -1);
  std::unordered_map<int32_t, int32_t> root_to_id;
  // The volumes' reference point: the bounds of the triangles whose indices are in range (as
  // mesh.bounds(), which would read past the end for the others).
  Eigen::AlignedBox3d box;
  for (const Triangle& tri : mesh.triangles) {
    if (std::all_of(tri.begin(), tri.end(),
                    [&](int32_t v) { return v >= 0 && v < mesh.vertex_count(); })) {
      for (int32_t v : tri) box.extend(mesh.positions[v]);
    }
  }
  const Eigen::Vector3d o = box.center();
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!usable[t]) continue;
    const int32_t root = sets.find(t);
    auto [it, inserted] = root_to_id.emplace(root, c.count);
    if (inserted) {
      ++c.count;
      c.stats.emplace_back();
    }
    c.of_triangle[t] = it->second;
    ComponentStats& s = c.stats[it->second];
    const Triangle& tri = mesh.triangles[t];
    s.triangles += 1;
    s.area += 0.5 * mesh.triangle_cross(t).norm();
    s.signed_volume += (mesh.positions[tri[0]] - o)
                           .dot((mesh.positions[tri[1]] - o).cross(mesh.positions[tri[2]] - o)) /
                       6.0;
  }
  return c;
}

OrientationSolve solve_orientation(const TriangleMesh& mesh, const std::vector<bool>& usable,
                                   const EdgeMap& edges, const Components& comps) {
  const size_t n = mesh.triangles.size();
  // Adjacency across edges with exactly two uses: "same" when the two triangles need the same
  // flip state (they traverse the edge in opposite directions).
  std::vector<std::vector<std::pair<int32_t, bool>>> adj(n);
  for (const auto& [key, uses] : edges) {
    if (uses.size() != 2) continue;
    const bool same = uses[0].forward != uses[1].forward;
    adj[uses[0].triangle].push_back({uses[1].triangle, same});
    adj[uses[1].triangle].push_back({uses[0].triangle, same});
  }
  OrientationSolve out;
  out.flip.assign(n, false);
  std::vector<int8_t> colour(n, -1);
  // Each component may split into several patches across non-manifold edges; colour each patch
  // and count flips per patch, then keep the minority per patch.
  std::vector<bool> component_bad(comps.count, false);
  for (size_t seed = 0; seed < n; ++seed) {
    if (!usable[seed] || colour[seed] >= 0) continue;
    std::vector<int32_t> patch;
    std::deque<int32_t> queue{static_cast<int32_t>(seed)};
    colour[seed] = 0;
    bool consistent = true;
    while (!queue.empty()) {
      const int32_t t = queue.front();
      queue.pop_front();
      patch.push_back(t);
      for (const auto& [u, same] : adj[t]) {
        const int8_t want = same ? colour[t] : static_cast<int8_t>(1 - colour[t]);
        if (colour[u] < 0) {
          colour[u] = want;
          queue.push_back(u);
        } else if (colour[u] != want) {
          consistent = false;
        }
      }
    }
    if (!consistent) component_bad[comps.of_triangle[seed]] = true;
    const auto ones =
        std::count_if(patch.begin(), patch.end(), [&](int32_t t) { return colour[t] == 1; });
    const int8_t minority = ones * 2 <= static_cast<int64_t>(patch.size()) ? 1 : 0;
    for (int32_t t : patch) {
      if (colour[t] == minority) {
        out.flip[t] = true;
        out.minority_triangles.push_back(t);
      }
    }
  }
  out.non_orientable_components =
      static_cast<int32_t>(std::count(component_bad.begin(), component_bad.end(), true));
  std::sort(out.minority_triangles.begin(), out.minority_triangles.end());
  return out;
}

std::vector<int32_t> find_non_manifold_vertices(const TriangleMesh& mesh,
                                                const std::vector<bool>& usable,
                                                const EdgeMap& edges) {
  // Incident triangles per vertex (CSR).
  const int32_t nv = mesh.vertex_count();
  std::vector<int32_t> start(nv + 1, 0);
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!usable[t]) continue;
    for (int32_t v : mesh.triangles[t]) ++start[v + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int32_t> incident(start[nv]);
  std::vector<int32_t> fill(start.begin(), start.end() - 1);
  for (int32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (!usable[t]) continue;
    for (int32_t v : mesh.triangles[t]) incident[fill[v]++] = t;
  }
  std::vector<int32_t> result;
  std::vector<int32_t> local;
  for (int32_t v = 0; v < nv; ++v) {
    const int32_t b = start[v];
    const int32_t e = start[v + 1];
    if (e - b < 2) continue;
    // Local union-find over this vertex's triangles joined by the edges (v, w) two share.
    local.assign(e - b, 0);
    std::iota(local.begin(), local.end(), 0);
    auto find = [&](int32_t x) {
      while (local[x] != x) x = local[x] = local[local[x]];
      return x;
    };
    for (int32_t i = b; i < e; ++i) {
      const Triangle& tri = mesh.triangles[incident[i]];
      for (int32_t w : tri) {
        if (w == v) continue;
        const auto it = edges.find(pack_edge(v, w));
        if (it == edges.end() || it->second.size() != 2) continue;
        for (int32_t j = b; j < e; ++j) {
          if (incident[j] == it->second[0].triangle || incident[j] == it->second[1].triangle) {
            const int32_t ra = find(i - b);
            const int32_t rb = find(j - b);
            if (ra != rb) local[ra] = rb;
          }
        }
      }
    }
    int32_t fans = 0;
    for (int32_t i = 0; i < e - b; ++i) fans += find(i) == i ? 1 : 0;
    if (fans > 1) result.push_back(v);
  }
  return result;
}

}  // namespace lap::haptics
