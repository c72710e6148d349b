#pragma once
/// \file
/// The project's fuzz targets as plain functions: each takes untrusted bytes through one reader
/// (the scenario loader, a mesh reader, the height-map loader, keyframe scripts, device and
/// session recordings, the gripper's USB reports) and everything the program does next with what
/// it accepted. The libFuzzer executables (fuzz_main.cpp, the `fuzz` preset) call them with
/// generated inputs; the ordinary test build replays the seed corpora and every input a fuzzer
/// ever crashed on (tests/fuzz/corpus, tests/fuzz/regressions) through the same functions, so a
/// crash once found stays fixed without clang.

#include <cstdint>
#include <span>
#include <string_view>

namespace lap::fuzz {

struct FuzzTarget {
  std::string_view name;  ///< the executable is fuzz_<name>; its corpus folder is corpus/<name>
  /// Runs the input through; true when the reader accepted it (false: refused with a message).
  bool (*run)(std::span<const uint8_t> data);
};

/// Every target, in a fixed order.
[[nodiscard]] std::span<const FuzzTarget> fuzz_targets();

/// The target called `name`, or nullptr.
[[nodiscard]] const FuzzTarget* find_fuzz_target(std::string_view name);

}  // namespace lap::fuzz
