#pragma once
/// \file
/// OpenHaptics' HD library, loaded at run time (dlopen of libHD.so) so that laptrainer builds
/// and runs on machines without it: a missing library is a clear message naming what to
/// install, never a failure to start.

#include <string>

namespace lap::hardware {

/// True when libHD.so can be loaded; otherwise false and *error says what to install.
bool open_haptics_available(std::string* error);

}  // namespace lap::hardware
