#pragma once
/// \file
/// Helpers shared by the test suites: where files are, temporary folders, running binaries.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "haptics/triangle_mesh.h"

namespace lap::test {

/// Long property tests run their full length in optimised builds; sanitizer builds, 10–50 times
/// slower, check the same properties on this fraction of the iterations so that CI stays short.
/// LAP_SANITIZER_BUILD comes from CMake's LAP_SANITIZER, which every sanitizer preset sets (the
/// compilers' own macros differ: clang 14 has no __SANITIZE_ADDRESS__).
#if defined(LAP_SANITIZER_BUILD)
inline constexpr int64_t kSanitizerDivisor = 20;
#else
inline constexpr int64_t kSanitizerDivisor = 1;
#endif

/// The project's source tree.
[[nodiscard]] std::filesystem::path source_dir();
/// ../shared/meshes beside the project, or "" when absent (a user's clone).
[[nodiscard]] std::filesystem::path shared_meshes_dir();
/// Directory of the built binaries.
[[nodiscard]] std::filesystem::path bin_dir();

/// A fresh empty directory under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  /// Writes text into a file below the directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

/// The whole file as bytes ("" when it cannot be read).
[[nodiscard]] std::string read_file(const std::filesystem::path& file);
/// `text` split at its newlines (a last line without one included).
[[nodiscard]] std::vector<std::string> lines_of(const std::string& text);

/// Result of running a command.
struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};
/// Runs a shell command, capturing stdout and stderr.
[[nodiscard]] CommandResult run_command(const std::string& command);

/// The angle between two vectors [rad], accurate near 0 and π (atan2 of |a × b| and a · b).
[[nodiscard]] double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// A closed, outward-oriented tetrahedron with its right-angle corner at offset.
[[nodiscard]] haptics::TriangleMesh tetrahedron(
    const Eigen::Vector3d& offset = Eigen::Vector3d::Zero(), double size = 1.0);

}  // namespace lap::test

/// Skips the current test when the shared meshes are absent.
#define LAP_REQUIRE_SHARED_MESHES()                                                    \
  do {                                                                                 \
    if (lap::test::shared_meshes_dir().empty()) {                                      \
      GTEST_SKIP() << "needs the real meshes in ../shared/meshes beside the project, " \
                      "which only the project's CI and developer machines have";       \
    }                                                                                  \
  } while (0)
