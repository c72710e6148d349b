#pragma once
/// \file
/// The project's own PLY reader (ascii, binary little- and big-endian). OpenMesh's reader was
/// replaced because fuzzing kept finding headers on which it loops for ever, printing a message
/// per element (an unknown element with a huge count, a first line 'PLY'): no check in front of
/// it could be sure to catch them all. This one reads the header to PLY's grammar, then exactly
/// the bytes or lines the header announces, every count bounded before anything is sized.
///
/// Read: the `vertex` element's x, y, z (required), nx, ny, nz and u, v (or s, t, texture_u,
/// texture_v) when present; the `face` element's vertex_indices (or vertex_index) list, polygons
/// fanned into triangles. Other elements and properties are read past and ignored.

#include <filesystem>

#include "core/result.h"
#include "haptics/triangle_mesh.h"

namespace lap::sim {

/// The mesh, or the first problem as `file:line: field: what` (ascii: the line; binary: the
/// element and byte offset in the message).
[[nodiscard]] Result<haptics::TriangleMesh> read_ply(const std::filesystem::path& file);

}  // namespace lap::sim
