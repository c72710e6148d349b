#pragma once
/// \file
/// Probe paths for `laptrainer-cli probe`: CSV rows of x,y,z (point) or x1,y1,z1,x2,y2,z2
/// (segment), metres, one row per haptic tick. An optional first line of column names is skipped.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/result.h"

namespace lap::sim {

/// An hour of ticks at 1 kHz, six numbers each, is about 250 MB: the largest path read.
inline constexpr std::uintmax_t kMaxProbePathBytes = std::uintmax_t{256} << 20;

/// Reads a path with `columns` numbers per row (3 or 6) from a regular file of at most
/// kMaxProbePathBytes. The diagnostic names the file, the line and what was expected.
[[nodiscard]] Result<std::vector<Eigen::Matrix<double, 6, 1>>> load_probe_path(
    const std::filesystem::path& file, int columns);

}  // namespace lap::sim
