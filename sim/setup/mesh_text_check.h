#pragma once
/// \file
/// Line-by-line checks of a mesh file before OpenMesh parses it. OpenMesh's readers drop a vertex
/// whose number they cannot read (`nan`, `inf`, `1e999`, `abc`) without a word, which shifts
/// every later index and leaves faces pointing past the end; they also size their arrays from
/// the counts in a header. So each number and index of a text file (OBJ; OFF and STL when they
/// are text) is checked here first and named by its line, and the counts in a header (OFF,
/// binary STL) are held to the limits of sim/setup/mesh_limits.h. PLY has its own reader
/// (sim/setup/ply_reader.h), which checks as it reads.

#include <filesystem>
#include <string>

#include "core/result.h"

namespace lap::sim {

/// The first problem found, as `file:line: field: what was expected` (e.g.
/// `mesh.obj:12: vertex: coordinate 'nan' is not a finite number`); success when the file's
/// numbers and indices are sound or the format is binary (checked after loading instead).
/// `ext` is the lower-case extension with its dot.
[[nodiscard]] Status check_mesh_text(const std::filesystem::path& file, const std::string& ext);

}  // namespace lap::sim
