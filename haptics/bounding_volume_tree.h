#pragma once
/// \file
/// Axis-aligned bounding-box tree over primitives (thesis §4.2, Figure 4-3) for the first-contact
/// segment query (§4.3). Built once per mesh: primitives are sorted along a Morton (Z-order) curve
/// of their centres and each range is split where the codes' highest differing bit changes, so
/// the build is a radix sort plus a linear pass (10^6 triangles in tens of milliseconds); boxes
/// come from one bottom-up refit. Refitted bottom-up, not rebuilt, when a mesh deforms. Boxes are
/// stored in float, rounded outward so that they always contain the double-precision geometry (no
/// contact is lost to rounding, however small the triangle). The query allocates nothing and never
/// throws.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace lap::haptics {

/// A node: a box, and either two children (count == 0: the left child is the next node, the
/// right child is at `first`) or a leaf range of primitives [first, first + count) in tree
/// order. Nodes are stored in pre-order, so leaves appear in primitive order and a reverse sweep
/// meets children before parents while reading the primitives sequentially.
struct BvhNode {
  std::array<float, 3> lo;
  std::array<float, 3> hi;
  int32_t first;
  int32_t count;
};

/// The points within r of the segment p0 -> p1.
struct Capsule {
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d p1 = Eigen::Vector3d::Zero();
  double r = 0.0;
};

/// The double-precision bounds a refit grows point by point before they are rounded outward to
/// a node's float box, with x and y as one SIMD pair (two comparisons per point instead of
/// four: a refit is mostly these comparisons). Each coordinate as `p < lo ? p : lo` and
/// `p > hi ? p : hi` (a NaN coordinate is ignored).
struct RefitBounds {
  Eigen::Array2d lo_xy = Eigen::Array2d::Constant(HUGE_VAL);
  Eigen::Array2d hi_xy = Eigen::Array2d::Constant(-HUGE_VAL);
  double lo_z = HUGE_VAL;
  double hi_z = -HUGE_VAL;
  void add(const Eigen::Vector3d& p) {
    const Eigen::Map<const Eigen::Array2d> xy(p.data());
    lo_xy = lo_xy.min(xy);  // Eigen's min(a, b) is b < a ? b : a, as std::min
    hi_xy = hi_xy.max(xy);
    lo_z = p.z() < lo_z ? p.z() : lo_z;
    hi_z = p.z() > hi_z ? p.z() : hi_z;
  }
};

/// The tree. Primitives are referred to by their position in tree order.
class BoundingVolumeTree {
 public:
  /// Largest depth the query's fixed stack supports; the build makes larger leaves instead.
  static constexpr int kMaxDepth = 60;

  /// Builds the tree's topology over n primitives with the given centres; order receives the
  /// tree order (order[k] = original index of the k-th primitive in tree order). The boxes are
  /// not set: call refit() with the primitives' boxes in tree order next.
  void build(const std::vector<Eigen::Vector3d>& centres, int32_t max_leaf_size,
             std::vector<int32_t>* order) {
    build(
        static_cast<int32_t>(centres.size()), [&centres](int32_t i) { return centres[i]; },
        max_leaf_size, order);
  }
  /// The same with the centres given by a function of the index (no array of them).
  template <typename Centre>
  void build(int32_t n, const Centre& centre, int32_t max_leaf_size, std::vector<int32_t>* order) {
    Eigen::AlignedBox3d bounds;
    for (int32_t i = 0; i < n; ++i) bounds.extend(centre(i));
    Eigen::Vector3d scale;
    for (int a = 0; a < 3; ++a) {
      const double extent = bounds.max()[a] - bounds.min()[a];
      scale[a] = extent > 0.0 ? 2097151.0 / extent : 0.0;
    }
    std::vector<uint64_t> codes(static_cast<size_t>(n));
    for (int32_t i = 0; i < n; ++i) codes[i] = morton_code(centre(i), bounds.min(), scale);
    build_from_codes(codes, max_leaf_size, order);
  }

  /// Recomputes every box, children before parents, in O(n); the topology is kept.
  /// extend(k, &bounds) grows a RefitBounds by primitive k (tree order).
  template <typename Extend>
  void refit(const Extend& extend) {
    for (auto i = static_cast<int64_t>(nodes_.size()) - 1; i >= 0; --i) {
      refit_node(static_cast<size_t>(i), extend);
    }
  }

  /// A local refit (§6.5: a dent moves a few primitives), kept up to date from one modelling
  /// step to the next: add() a primitive when it starts moving, remove() it when it stops. A
  /// leaf is marked while it holds an added primitive, an inner node while a child is marked
  /// (counts, so a dent sliding along the surface only adds and removes at its edges instead of
  /// marking its whole region afresh every step). refit_marked() recomputes the marked nodes,
  /// children first; equal to refit() whenever the primitives not added did not move. Sized once
  /// for its tree (setup); add, remove and refit allocate nothing.
  struct PartialRefit {
    explicit PartialRefit(const BoundingVolumeTree& tree);
    /// One more reason to refit leaf i (a node index, as leaf_of gives it): marks it and its
    /// ancestors when it had none.
    void add_to_leaf(int32_t i) {
      while (i >= 0 && count[static_cast<size_t>(i)]++ == 0) {
        flip(i);
        i = parent[static_cast<size_t>(i)];
      }
    }
    /// One reason fewer: unmarks the leaf when none is left, and each ancestor left with no
    /// marked child.
    void remove_from_leaf(int32_t i) {
      while (i >= 0 && --count[static_cast<size_t>(i)] == 0) {
        flip(i);
        i = parent[static_cast<size_t>(i)];
      }
    }
    /// The same for primitive k (tree order): its leaf.
    void add(int32_t k) { add_to_leaf(leaf_of[static_cast<size_t>(k)]); }
    void remove(int32_t k) { remove_from_leaf(leaf_of[static_cast<size_t>(k)]); }
    /// Unmarks everything (O(nodes)).
    void clear();
    [[nodiscard]] bool marked(int32_t i) const {
      return ((marks[static_cast<size_t>(i) >> 6U] >> (static_cast<unsigned>(i) & 63U)) & 1U) != 0;
    }
    std::vector<int32_t> count;       // per node: a leaf's reasons, an inner node's marked children
    std::vector<uint64_t> marks;      // bit i of word i / 64: node i is marked
    std::vector<uint64_t> leaf_bits;  // the same layout: node i is a leaf
    std::vector<int32_t> parent;      // per node, -1 for the root
    std::vector<int32_t> leaf_of;     // per primitive (tree order)

   private:
    void flip(int32_t i) {
      marks[static_cast<size_t>(i) >> 6U] ^= uint64_t{1} << (static_cast<unsigned>(i) & 63U);
    }
  };

  /// Refits the nodes marked in `r` (see PartialRefit); extend as for refit(). The leaves first
  /// (they have no children), then the inner nodes from the highest index down: nodes are stored
  /// in pre-order, every child after its parent, so that refits children first. Two walks over
  /// the marks (masked by leaf_bits), not one with a leaf-or-not branch per node, which
  /// mispredicts about every other node; both read the nodes in memory order. Each walk reads one
  /// bit per node of the tree (a 10^6-triangle mesh: 8 000 words). No allocation.
  template <typename Extend>
  void refit_marked(const PartialRefit& r, const Extend& extend) {
    for (size_t w = 0; w < r.marks.size(); ++w) {
      for (uint64_t bits = r.marks[w] & r.leaf_bits[w]; bits != 0; bits &= bits - 1) {
        refit_leaf(w * 64 + static_cast<size_t>(std::countr_zero(bits)), extend);
      }
    }
    for (size_t w = r.marks.size(); w-- > 0;) {
      for (uint64_t bits = r.marks[w] & ~r.leaf_bits[w]; bits != 0;) {
        const int b = 63 - std::countl_zero(bits);
        bits ^= uint64_t{1} << static_cast<unsigned>(b);
        refit_inner(w * 64 + static_cast<size_t>(b));
      }
    }
  }

  /// Visits the leaves whose boxes the segment p0 -> p1 touches, nearest first. `visit(k, t_max)`
  /// tests primitive k (tree order) and returns the hit parameter t in [0, t_max], or a negative
  /// number for no hit. Returns the smallest hit t and its primitive, or -1.
  template <typename Visit>
  int32_t first_hit(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Visit& visit,
                    double* t_hit) const {
    if (nodes_.empty()) return -1;
    const Eigen::Vector3d d = p1 - p0;
    Eigen::Vector3d inv;
    for (int a = 0; a < 3; ++a) inv[a] = d[a] != 0.0 ? 1.0 / d[a] : std::copysign(1e300, d[a]);
    double best_t = 1.0;
    int32_t best = -1;
    std::array<int32_t, kMaxDepth + 4> stack{};
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const BvhNode& node = nodes_[stack[--top]];
      if (!segment_touches(node, p0, inv, best_t)) continue;
      if (node.count > 0) {
        for (int32_t k = node.first; k < node.first + node.count; ++k) {
          const double t = visit(k, best_t);
          if (t >= 0.0 && t <= best_t) {
            best_t = t;
            best = k;
          }
        }
      } else {
        // Near child last, so it is popped first.
        const int32_t a = static_cast<int32_t>(&node - nodes_.data()) + 1;
        const int32_t b = node.first;
        const double ta = entry(nodes_[a], p0, inv);
        const double tb = entry(nodes_[b], p0, inv);
        if (ta <= tb) {
          stack[top++] = b;
          stack[top++] = a;
        } else {
          stack[top++] = a;
          stack[top++] = b;
        }
      }
    }
    if (t_hit != nullptr) *t_hit = best_t;
    return best;
  }

  /// The primitive nearest p, by branch and bound: `visit(k, best_d2)` returns the squared
  /// distance from p to primitive k (tree order); nodes whose boxes lie farther than the best so
  /// far are skipped, the nearer child is searched first. Returns the primitive (-1 for an
  /// empty tree) and its squared distance in *d2. No allocation.
  template <typename Visit>
  int32_t nearest(const Eigen::Vector3d& p, const Visit& visit, double* d2) const {
    double best_d2 = std::numeric_limits<double>::infinity();
    int32_t best = -1;
    std::array<int32_t, kMaxDepth + 4> stack{};
    int top = 0;
    if (!nodes_.empty()) stack[top++] = 0;
    while (top > 0) {
      const BvhNode& node = nodes_[stack[--top]];
      if (box_distance2(node, p) >= best_d2) continue;
      if (node.count > 0) {
        for (int32_t k = node.first; k < node.first + node.count; ++k) {
          const double d = visit(k, best_d2);
          if (d < best_d2) {
            best_d2 = d;
            best = k;
          }
        }
      } else {
        const int32_t a = static_cast<int32_t>(&node - nodes_.data()) + 1;
        const int32_t b = node.first;
        const bool a_first = box_distance2(nodes_[a], p) <= box_distance2(nodes_[b], p);
        stack[top++] = a_first ? b : a;  // the nearer child last, so it is popped first
        stack[top++] = a_first ? a : b;
      }
    }
    if (d2 != nullptr) *d2 = best_d2;
    return best;
  }

  /// Squared distance from p to a node's box (0 inside).
  static double box_distance2(const BvhNode& n, const Eigen::Vector3d& p) {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double below = static_cast<double>(n.lo[a]) - p[a];
      const double above = p[a] - static_cast<double>(n.hi[a]);
      const double out = std::max({below, above, 0.0});
      d2 += out * out;
    }
    return d2;
  }

  /// Visits every primitive k (tree order) in a leaf whose box, grown by r on every side, the
  /// segment p0 -> p1 touches: a conservative cover of the capsule of radius r around the
  /// segment (the volume a moving segment sweeps, §5.3). `visit(k)` is called once per such
  /// primitive, in no particular order.
  template <typename Visit>
  void for_each_near_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double r,
                             const Visit& visit) const {
    for_each_near_capsules({p0, p1, r}, {}, visit);
  }

  /// The same for the union of up to kMaxCapsules capsules (pieces) in one traversal, a tapered
  /// capsule cut into pieces: each primitive is visited once, where separate queries would walk
  /// the shared upper levels of the tree once per piece and visit shared primitives repeatedly.
  /// `hull` must contain every piece: a node it misses is rejected with one test instead of one
  /// per piece (most nodes visited are such rejections). No pieces: the hull itself.
  static constexpr int kMaxCapsules = 4;
  template <typename Visit>
  void for_each_near_capsules(const Capsule& hull, std::span<const Capsule> pieces,
                              const Visit& visit) const {
    if (nodes_.empty()) return;
    const size_t count = std::min(pieces.size(), static_cast<size_t>(kMaxCapsules));
    const Eigen::Vector3d hull_inv = inverse_direction(hull);
    std::array<Eigen::Vector3d, kMaxCapsules> inv;
    for (size_t c = 0; c < count; ++c) inv[c] = inverse_direction(pieces[c]);
    std::array<int32_t, kMaxDepth + 4> stack{};
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const int32_t i = stack[--top];
      const BvhNode& node = nodes_[i];
      if (!segment_touches_grown(node, hull.p0, hull_inv, hull.r)) continue;
      bool touches = count == 0;
      for (size_t c = 0; c < count && !touches; ++c) {
        touches = segment_touches_grown(node, pieces[c].p0, inv[c], pieces[c].r);
      }
      if (!touches) continue;
      if (node.count > 0) {
        for (int32_t k = node.first; k < node.first + node.count; ++k) visit(k);
      } else {
        stack[top++] = node.first;
        stack[top++] = i + 1;
      }
    }
  }

  /// Whether the segment p0 -> p1 (a point when they are equal) touches the root's box, which
  /// bounds every primitive: first_hit's first test, on its own. False for an empty tree.
  [[nodiscard]] bool segment_touches_bounds(const Eigen::Vector3d& p0,
                                            const Eigen::Vector3d& p1) const {
    if (nodes_.empty()) return false;
    return segment_touches(nodes_.front(), p0, inverse_direction(Capsule{p0, p1, 0.0}), 1.0);
  }
  [[nodiscard]] const std::vector<BvhNode>& nodes() const { return nodes_; }
  [[nodiscard]] int32_t depth() const { return depth_; }
  [[nodiscard]] size_t memory_bytes() const { return nodes_.capacity() * sizeof(BvhNode); }

  /// 63-bit Morton code of p: 21 bits per axis of (p - origin) * scale, clamped.
  static uint64_t morton_code(const Eigen::Vector3d& p, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& scale);

  /// Stores a double box in float, rounded outward.
  static void set_box(BvhNode& node, const Eigen::AlignedBox3d& box);

 private:
  // Node i's box: a leaf's from its primitives (rounded outward), an inner node's as the union
  // of its children's (already rounded outward: their float union is exact).
  template <typename Extend>
  void refit_node(size_t i, const Extend& extend) {
    if (nodes_[i].count > 0) {
      refit_leaf(i, extend);
    } else {
      refit_inner(i);
    }
  }
  template <typename Extend>
  void refit_leaf(size_t i, const Extend& extend) {
    BvhNode& node = nodes_[i];
    RefitBounds bounds;
    for (int32_t k = node.first; k < node.first + node.count; ++k) extend(k, &bounds);
    node.lo = {float_below(bounds.lo_xy[0]), float_below(bounds.lo_xy[1]),
               float_below(bounds.lo_z)};
    node.hi = {float_above(bounds.hi_xy[0]), float_above(bounds.hi_xy[1]),
               float_above(bounds.hi_z)};
  }
  void refit_inner(size_t i) {
    BvhNode& node = nodes_[i];
    const BvhNode& a = nodes_[i + 1];
    const BvhNode& b = nodes_[static_cast<size_t>(node.first)];
    for (int c = 0; c < 3; ++c) {
      node.lo[c] = std::min(a.lo[c], b.lo[c]);
      node.hi[c] = std::max(a.hi[c], b.hi[c]);
    }
  }
  // Outward rounding without branches (a refit does it for every leaf, and a data-dependent
  // branch here mispredicts half the time): convert to the nearest float, then always step one
  // float further out. The box may be one float step wider than needed; it is never narrower.
  static float float_below(double x) {
    const auto f = static_cast<float>(x);
    auto b = std::bit_cast<uint32_t>(f);
    // Positive: one step smaller; zero or negative: one step more negative (-0 and +0 alike).
    b = f > 0.0f ? b - 1U : (b | 0x80000000U) + 1U;
    return std::bit_cast<float>(b);
  }
  static float float_above(double x) {
    const auto f = static_cast<float>(x);
    auto b = std::bit_cast<uint32_t>(f);
    b = f < 0.0f ? b - 1U : (b & 0x7fffffffU) + 1U;
    return std::bit_cast<float>(b);
  }

  void build_from_codes(std::vector<uint64_t>& codes, int32_t max_leaf_size,
                        std::vector<int32_t>* order);
  static bool segment_touches(const BvhNode& n, const Eigen::Vector3d& p0,
                              const Eigen::Vector3d& inv, double t_max) {
    double t0 = 0.0;
    double t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      double ta = (static_cast<double>(n.lo[a]) - p0[a]) * inv[a];
      double tb = (static_cast<double>(n.hi[a]) - p0[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      // NaN (0 * inf for a segment lying in a slab face) compares false: keep the interval.
      if (ta > t0) t0 = ta;
      if (tb < t1) t1 = tb;
      if (t0 > t1) return false;
    }
    return true;
  }
  // 1 / (p1 - p0) per axis, an axis the segment does not move along as a huge number of its
  // sign (the slab test then keeps or rejects the whole segment on that axis).
  static Eigen::Vector3d inverse_direction(const Capsule& c) {
    const Eigen::Vector3d d = c.p1 - c.p0;
    Eigen::Vector3d inv;
    for (int a = 0; a < 3; ++a) inv[a] = d[a] != 0.0 ? 1.0 / d[a] : std::copysign(1e300, d[a]);
    return inv;
  }
  static bool segment_touches_grown(const BvhNode& n, const Eigen::Vector3d& p0,
                                    const Eigen::Vector3d& inv, double r) {
    double t0 = 0.0;
    double t1 = 1.0;
    for (int a = 0; a < 3; ++a) {
      double ta = (static_cast<double>(n.lo[a]) - r - p0[a]) * inv[a];
      double tb = (static_cast<double>(n.hi[a]) + r - p0[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      if (ta > t0) t0 = ta;
      if (tb < t1) t1 = tb;
      if (t0 > t1) return false;
    }
    return true;
  }
  static double entry(const BvhNode& n, const Eigen::Vector3d& p0, const Eigen::Vector3d& inv) {
    double t0 = 0.0;
    for (int a = 0; a < 3; ++a) {
      double ta = (static_cast<double>(n.lo[a]) - p0[a]) * inv[a];
      double tb = (static_cast<double>(n.hi[a]) - p0[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      if (ta > t0) t0 = ta;
    }
    return t0;
  }

  std::vector<BvhNode> nodes_;
  int32_t depth_ = 0;
};

}  // namespace lap::haptics
