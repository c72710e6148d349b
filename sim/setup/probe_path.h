#pragma once
/// \file
/// Probe paths for `laptrainer-cli probe`: CSV rows of x,y,z (point) or x1,y1,z1,x2,y2,z2
/// (segment), metres, one row per haptic tick. An optional first line of column names is skipped.

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "core/result.h"

namespace lap::sim {

/// Reads a path with `columns` numbers per row (3 or 6). The diagnostic names the file, the
/// line and what was expected.
[[nodiscard]] Result<std::vector<Eigen::Matrix<double, 6, 1>>> load_probe_path(
    const std::filesystem::path& file, int columns);

}  // namespace lap::sim
