#pragma once
/// \file
/// The error type of all loading code in sim/: a message that already names the file, the line
/// (where there is one), the field and what was expected.

#include <stdexcept>
#include <string>

namespace lap::sim {

/// Thrown by loaders (setup code only; the real-time step never throws).
class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace lap::sim
