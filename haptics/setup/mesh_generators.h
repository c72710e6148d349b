#pragma once
/// \file
/// Closed, outward-oriented meshes generated from parameters: test shapes with analytic answers
/// (sphere, box, cylinder) and the project's own stand-in organ shapes for the introductory
/// scenario (scenarios/introductory.yaml).

#include <cstdint>
#include <functional>

#include "haptics/triangle_mesh.h"

namespace lap::haptics {

/// Sphere by latitude/longitude: 2 * slices * (stacks - 1) triangles, closed with pole fans.
[[nodiscard]] TriangleMesh make_uv_sphere(double radius, int32_t stacks, int32_t slices);

/// Axis-aligned box centred at the origin, each face split into n x n squares (2n^2 triangles
/// per face).
[[nodiscard]] TriangleMesh make_box(const Eigen::Vector3d& size, int32_t n = 1);

/// Closed cylinder along +y from y = 0 to y = length, capped with fans; the side has
/// `rings` rows of quads.
[[nodiscard]] TriangleMesh make_cylinder(double radius, double length, int32_t slices,
                                         int32_t rings = 1);

/// Open square plate of zero thickness in the y = 0 plane, centred at the origin, normal +y,
/// split into n x n squares: a thin two-sided object (thesis Figure 4-6).
[[nodiscard]] TriangleMesh make_plate(double size, int32_t n);

/// Closed solid made of unit cells of the given size: occupied(i, j, k) for i < nx, j < ny,
/// k < nz; each cell face between an occupied and an empty cell becomes two triangles. Cells
/// must not touch only along an edge or a corner (the result would be non-manifold).
[[nodiscard]] TriangleMesh make_voxel_solid(
    int32_t nx, int32_t ny, int32_t nz, double cell,
    const std::function<bool(int32_t, int32_t, int32_t)>& occupied);

/// Open hemispherical bowl of the given radius, centred at the origin, rim at y = 0, opening
/// up; its front (normal) side is the inside of the bowl.
[[nodiscard]] TriangleMesh make_bowl(double radius, int32_t stacks, int32_t slices);

/// A sphere whose unit-sphere points are mapped by f: for organ-like blobs. f must keep the
/// surface embedded (no self-intersection) for the result to be valid.
[[nodiscard]] TriangleMesh make_mapped_sphere(
    int32_t stacks, int32_t slices,
    const std::function<Eigen::Vector3d(const Eigen::Vector3d& unit)>& f);

/// The project's stand-in organs (metres, world frame y up), generated for the introductory
/// scenario; real scans are for tests only (../shared/meshes).
[[nodiscard]] TriangleMesh make_stand_in_liver();
[[nodiscard]] TriangleMesh make_stand_in_gallbladder();
[[nodiscard]] TriangleMesh make_stand_in_cystic_duct();

}  // namespace lap::haptics
