#pragma once
/// \file
/// The duct's modes cached on disk (issue 6): keyed by everything they depend on (mesh, held
/// degrees of freedom, material, mode count), so start-up reads them instead of solving again.
/// A missing, corrupt or foreign file is rebuilt, and the caller is told why; an unwritable
/// cache directory only costs the next start-up its time.

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"
#include "models/modal_shell.h"

namespace lap::sim {

/// $LAPTRAINER_CACHE_DIR, else $XDG_CACHE_HOME/laptrainer/modes, else ~/.cache/laptrainer/modes.
[[nodiscard]] std::filesystem::path default_mode_cache_dir();

struct ModalShellLoad {
  models::ModalShellModel model;
  bool from_cache = false;
  std::string note;      ///< why it was rebuilt or not written; empty when all went well
  double seconds = 0.0;  ///< wall time of the load or build
  std::filesystem::path file;
};

/// Reads the modes from `dir` or builds and writes them; the diagnostic says why they could not be
/// built (bad mesh or settings: ModalShellModel::build's reason).
[[nodiscard]] Result<ModalShellLoad> load_or_build_modal_shell(
    const models::ShellMesh& mesh, const std::vector<uint8_t>& held_dof,
    const models::ModalShellSettings& settings, const std::filesystem::path& dir);

}  // namespace lap::sim
