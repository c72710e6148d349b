#include "sim/setup/modal_shell_cache.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <system_error>

#include "core/bounded_file.h"

namespace lap::sim {
namespace {
/// A duct's shell of a few thousand nodes and some sixty modes is a few megabytes.
constexpr std::uintmax_t kMaxModeCacheBytes = std::uintmax_t{1} << 30;
}  // namespace

std::filesystem::path default_mode_cache_dir() {
  if (const char* d = std::getenv("LAPTRAINER_CACHE_DIR"); d != nullptr && *d != '\0') {
    return std::filesystem::path(d);
  }
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && *x != '\0') {
    return std::filesystem::path(x) / "laptrainer" / "modes";
  }
  if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0') {
    return std::filesystem::path(h) / ".cache" / "laptrainer" / "modes";
  }
  return std::filesystem::temp_directory_path() / "laptrainer-modes";
}

Result<ModalShellLoad> load_or_build_modal_shell(const models::ShellMesh& mesh,
                                                 const std::vector<uint8_t>& held_dof,
                                                 const models::ModalShellSettings& settings,
                                                 const std::filesystem::path& dir) {
  const auto start = std::chrono::steady_clock::now();
  const uint64_t key = models::ModalShellModel::key(mesh, held_dof, settings);
  char name[40];
  std::snprintf(name, sizeof name, "modes-%016llx.bin", static_cast<unsigned long long>(key));
  const std::filesystem::path file = dir / name;
  std::string note;
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::symlink_status(file, ec))) {
    // The cache is the program's own, but in the user's folders: anything there that is not a
    // regular file of a sane size (a FIFO would block the read for ever) is rebuilt over.
    const Result<std::string> read = read_bounded_file(file, kMaxModeCacheBytes, "a mode cache");
    if (!read.ok()) {
      note = read.message() + "; rebuilt";
    } else {
      const std::vector<uint8_t> bytes(read.value().begin(), read.value().end());
      try {
        ModalShellLoad r{models::ModalShellModel::from_bytes(bytes, key, settings), true, "", 0.0,
                         file};
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return r;
      } catch (const std::invalid_argument& e) {
        note = file.string() + ": " + e.what() + "; rebuilt";
      }
    }
  }
  std::optional<models::ModalShellModel> built;
  try {  // the models library refuses a bad mesh or settings with std::invalid_argument
    built.emplace(models::ModalShellModel::build(mesh, held_dof, settings));
  } catch (const std::invalid_argument& e) {
    return diagnostic(e.what());
  }
  ModalShellLoad r{std::move(*built), false, note, 0.0, file};
  const std::vector<uint8_t> bytes = r.model.to_bytes(key);
  std::filesystem::create_directories(dir, ec);
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    if (!out) {
      r.note += (r.note.empty() ? "" : "; ") +
                ("could not write " + tmp.string() + ": the modes will be solved again next start");
    }
  }
  if (r.note.find("could not write") == std::string::npos) {
    std::filesystem::rename(tmp, file, ec);  // atomic: a reader never sees half a file
    if (ec) r.note += (r.note.empty() ? "" : "; ") + ("could not rename into " + file.string());
  }
  std::filesystem::remove(tmp, ec);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace lap::sim
