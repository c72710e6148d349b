#pragma once
/// \file
/// A file's fingerprint: FNV-1a 64 of its bytes. A recorded session keeps its scenario's
/// (session.json's `scenario_digest`), taken from the very bytes the loader parsed
/// (Scenario::digest), so that a review can say when the scenario it replays is not the one the
/// session ran, and a run can say when the file changed on disk while it ran. Not a
/// cryptographic hash: it tells changes apart, it does not authenticate.

#include <cstdint>
#include <filesystem>
#include <string_view>

#include "core/result.h"

namespace lap::sim {

/// FNV-1a 64 of `bytes`.
[[nodiscard]] uint64_t content_digest(std::string_view bytes);

/// FNV-1a 64 of a scenario file (a regular file of at most `max_bytes`); diagnostics name the
/// file when it cannot be read (core/bounded_file.h).
[[nodiscard]] Result<uint64_t> file_digest(const std::filesystem::path& file,
                                           std::uintmax_t max_bytes);

}  // namespace lap::sim
