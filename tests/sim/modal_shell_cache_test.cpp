// The duct's modes: the default duct's precomputation, and the on-disk cache (hit, key
// change, corrupt file, unwritable directory).

#include "sim/setup/modal_shell_cache.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "tests/test_support.h"

namespace lap::sim {
namespace {

TEST(ModalShellCache, DefaultDuctIsSolvedOnceThenRead) {
  const test::TempDir tmp;
  const models::DuctSettings duct;
  const models::DuctShell shell = models::make_duct_shell(duct);
  const models::ModalShellSettings settings = models::default_duct_modal_settings(duct);
  const ModalShellLoad built =
      load_or_build_modal_shell(shell.mesh, shell.held_dof, settings, tmp.path()).value();
  EXPECT_FALSE(built.from_cache);
  EXPECT_TRUE(built.note.empty()) << built.note;
  // How long the solve takes is printed below and measured by the benchmarks
  // (docs/benchmarks.md), not asserted: a loaded or instrumented build may take any time.
  ASSERT_TRUE(std::filesystem::exists(built.file));
  const ModalShellLoad read =
      load_or_build_modal_shell(shell.mesh, shell.held_dof, settings, tmp.path()).value();
  EXPECT_TRUE(read.from_cache);
  EXPECT_EQ(read.model.omega(), built.model.omega());
  EXPECT_EQ(read.model.modes(), built.model.modes());
  std::printf(
      "[ modal cache ] default duct (%zu nodes, %d modes, %.1f-%.1f Hz): solved in %.2f s, "
      "read in %.3f s\n",
      shell.mesh.nodes.size(), built.model.mode_count(), built.model.omega()(0) / (2 * M_PI),
      built.model.omega()(built.model.mode_count() - 1) / (2 * M_PI), built.seconds, read.seconds);
  // Another material is another key: solved again, not read.
  models::ModalShellSettings stiffer = settings;
  stiffer.material.young_pa *= 2.0;
  const ModalShellLoad other =
      load_or_build_modal_shell(shell.mesh, shell.held_dof, stiffer, tmp.path()).value();
  EXPECT_FALSE(other.from_cache);
  EXPECT_NEAR(other.model.omega()(0), std::sqrt(2.0) * built.model.omega()(0),
              1e-6 * built.model.omega()(0));
}

// A coarse duct with few modes: quick to solve, for the cache's failure paths.
struct SmallDuct {
  models::DuctSettings duct;
  models::DuctShell shell;
  models::ModalShellSettings settings;
  SmallDuct() {
    duct.around = 12;
    duct.along = 10;
    shell = models::make_duct_shell(duct);
    settings = models::default_duct_modal_settings(duct);
    settings.modes = 8;
  }
};

TEST(ModalShellCache, CorruptFileIsRebuiltAndSaid) {
  const test::TempDir tmp;
  const SmallDuct small;
  const models::DuctShell& shell = small.shell;
  const models::ModalShellSettings& settings = small.settings;
  const ModalShellLoad built =
      load_or_build_modal_shell(shell.mesh, shell.held_dof, settings, tmp.path()).value();
  {
    std::ofstream out(built.file, std::ios::binary | std::ios::trunc);
    out << "garbage";
  }
  const ModalShellLoad again =
      load_or_build_modal_shell(shell.mesh, shell.held_dof, settings, tmp.path()).value();
  EXPECT_FALSE(again.from_cache);
  EXPECT_NE(again.note.find(built.file.string()), std::string::npos) << again.note;
  EXPECT_NE(again.note.find("too short"), std::string::npos) << again.note;
  EXPECT_EQ(again.model.omega(), built.model.omega());
  // And the rewritten file is good again.
  EXPECT_TRUE(load_or_build_modal_shell(shell.mesh, shell.held_dof, settings, tmp.path())
                  .value()
                  .from_cache);
}

TEST(ModalShellCache, UnwritableDirectoryStillBuilds) {
  const test::TempDir tmp;
  const std::filesystem::path file = tmp.write("not_a_dir", "x");
  const SmallDuct small;
  const ModalShellLoad r = load_or_build_modal_shell(small.shell.mesh, small.shell.held_dof,
                                                     small.settings, file / "modes")
                               .value();
  EXPECT_FALSE(r.from_cache);
  EXPECT_NE(r.note.find("could not write"), std::string::npos) << r.note;
  EXPECT_EQ(r.model.mode_count(), 8);
}

TEST(ModalShellCache, TheDuctIsHeldByItsEndsAndMembrane) {
  const models::DuctSettings duct;
  const models::DuctShell shell = models::make_duct_shell(duct);
  const models::ModalShellSettings settings = models::default_duct_modal_settings(duct);
  const models::ModalShellModel model =
      models::ModalShellModel::build(shell.mesh, shell.held_dof, settings);
  // A poke on the top of the middle ring dents it; the held rows of every mode are zero.
  models::ModalShellState state(model);
  const int32_t top = duct.along / 2 * duct.around + duct.around / 4;  // angle +90°
  for (int k = 0; k < 2000; ++k) {
    models::apply_node_force(&state, top, Eigen::Vector3d(0.0, -0.01, 0.0));
    ASSERT_TRUE(models::step_modal_shell(model, &state, 0.005));
  }
  EXPECT_LT(state.displacement[top].y(), -1e-5);
  for (size_t d = 0; d < shell.held_dof.size(); ++d) {
    if (shell.held_dof[d] != 0) {
      ASSERT_EQ(model.modes().row(static_cast<Eigen::Index>(d)).norm(), 0.0) << d;
    }
  }
  std::printf("[ modal cache ] default duct poked with 10 mN on top: dent %.3f mm\n",
              -1e3 * state.displacement[top].y());
}

// Where the modes go: the override first, then the XDG cache, then the home directory.
TEST(ModalShellCache, DefaultDirectoryFollowsTheEnvironment) {
  const char* saved_override = std::getenv("LAPTRAINER_CACHE_DIR");
  const char* saved_xdg = std::getenv("XDG_CACHE_HOME");
  const std::string keep_override = saved_override != nullptr ? saved_override : "";
  const std::string keep_xdg = saved_xdg != nullptr ? saved_xdg : "";
  setenv("LAPTRAINER_CACHE_DIR", "/tmp/lap-modes", 1);
  setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  EXPECT_EQ(default_mode_cache_dir(), std::filesystem::path("/tmp/lap-modes"));
  unsetenv("LAPTRAINER_CACHE_DIR");
  EXPECT_EQ(default_mode_cache_dir(), std::filesystem::path("/tmp/xdg/laptrainer/modes"));
  unsetenv("XDG_CACHE_HOME");
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    EXPECT_EQ(default_mode_cache_dir(),
              std::filesystem::path(home) / ".cache" / "laptrainer" / "modes");
  }
  if (saved_override != nullptr) setenv("LAPTRAINER_CACHE_DIR", keep_override.c_str(), 1);
  if (saved_xdg != nullptr) setenv("XDG_CACHE_HOME", keep_xdg.c_str(), 1);
}

}  // namespace
}  // namespace lap::sim
