#pragma once
/// \file
/// The catheter drawn as a tube of its real diameter along its particles (§7.7(3): the
/// mass-spring catheter's centre line): a ring of `sides` vertices round each particle, in the
/// plane across the centre line there, each ring's frame carried from the last by parallel
/// transport (the smallest turn), so the tube does not twist as the catheter bends; the tip
/// closed by a rounded cap. The topology is fixed when the tube is made; each frame only the
/// vertices and normals are written, into the caller's float buffers (no allocation).

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace lap::app {

class CatheterTube {
 public:
  /// A tube over `particles` centre-line points, `sides` vertices round.
  CatheterTube(int32_t particles, int32_t sides);

  [[nodiscard]] int32_t vertex_count() const { return vertex_count_; }
  /// Triangles as vertex index triples, counter-clockwise seen from outside.
  [[nodiscard]] const std::vector<int32_t>& triangles() const { return triangles_; }

  /// Writes the vertices and unit normals (vertex_count() x 3 floats each) for the centre line
  /// `centre_W` (as many points as the tube was made for; the last is the tip) and `radius_m`.
  /// Returns false (and writes nothing) for a centre line of another length.
  bool write(std::span<const Eigen::Vector3d> centre_W, double radius_m, std::span<float> points,
             std::span<float> normals) const;

 private:
  int32_t particles_;
  int32_t sides_;
  int32_t vertex_count_;
  std::vector<int32_t> triangles_;
};

}  // namespace lap::app
