#pragma once
/// \file
/// The exception the loaders of sim/setup/ throw inside themselves while they read a file; each
/// public loader catches it and returns its Diagnostic in a Result (core/result.h), so no
/// exception leaves set-up code (and the real-time step never throws).

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/diagnostic.h"

namespace lap::sim {

class LoadError : public std::runtime_error {
 public:
  explicit LoadError(Diagnostic d) : std::runtime_error(d.to_string()), diagnostic_(std::move(d)) {}
  /// A problem with `file` as a whole (no line).
  LoadError(const std::filesystem::path& file, std::string message)
      : LoadError(Diagnostic{file.string(), 0, "", std::move(message)}) {}
  [[nodiscard]] const Diagnostic& diagnostic() const { return diagnostic_; }

 private:
  Diagnostic diagnostic_;
};

}  // namespace lap::sim
