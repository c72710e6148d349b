#pragma once
/// \file
/// Result<T>: a value, or the diagnostics that say why there is none (Jolt's Result, Box2D's
/// settings-to-create habit; std::expected is C++23). Set-up code returns it; the real-time step
/// never does (it reports faults through the watchdog instead). Status is Result<void>.

#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/diagnostic.h"

namespace lap {

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}         // NOLINT(google-explicit-constructor)
  Result(Diagnostic d) : diagnostics_{std::move(d)} {}  // NOLINT(google-explicit-constructor)
  Result(std::vector<Diagnostic> d)                     // NOLINT(google-explicit-constructor)
      : diagnostics_(std::move(d)) {
    if (diagnostics_.empty()) diagnostics_.push_back(diagnostic("failed (no diagnostic given)"));
  }

  [[nodiscard]] bool ok() const { return value_.has_value(); }
  explicit operator bool() const { return ok(); }
  /// The value. Asking for it when there is none is the caller's mistake: it throws
  /// std::runtime_error with the diagnostics (as std::expected::value() throws), so a test that
  /// expected success fails with the reason instead of reading garbage.
  [[nodiscard]] T& value() & {
    check();
    return *value_;
  }
  [[nodiscard]] const T& value() const& {
    check();
    return *value_;
  }
  [[nodiscard]] T&& value() && {
    check();
    return std::move(*value_);
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  /// Why there is no value; empty when ok(). A temporary Result hands its diagnostics over by
  /// value, so `for (const Diagnostic& d : load(...).diagnostics())` does not dangle.
  [[nodiscard]] const std::vector<Diagnostic>& diagnostics() const& { return diagnostics_; }
  [[nodiscard]] std::vector<Diagnostic> diagnostics() && { return std::move(diagnostics_); }
  /// The diagnostics, one per line.
  [[nodiscard]] std::string message() const { return to_string(diagnostics_); }

 private:
  void check() const {
    if (!ok()) throw std::runtime_error(message());
  }
  std::optional<T> value_;
  std::vector<Diagnostic> diagnostics_;
};

/// Success, or the diagnostics that say what went wrong.
template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Diagnostic d) : diagnostics_{std::move(d)} {}  // NOLINT(google-explicit-constructor)
  Result(std::vector<Diagnostic> d)                     // NOLINT(google-explicit-constructor)
      : diagnostics_(std::move(d)) {}
  [[nodiscard]] bool ok() const { return diagnostics_.empty(); }
  explicit operator bool() const { return ok(); }
  [[nodiscard]] const std::vector<Diagnostic>& diagnostics() const& { return diagnostics_; }
  [[nodiscard]] std::vector<Diagnostic> diagnostics() && { return std::move(diagnostics_); }
  [[nodiscard]] std::string message() const { return to_string(diagnostics_); }

 private:
  std::vector<Diagnostic> diagnostics_;
};
using Status = Result<void>;

}  // namespace lap
