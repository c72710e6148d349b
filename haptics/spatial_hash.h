#pragma once
/// \file
/// A 32-bit integer hash (multiply-xorshift with full avalanche) for reproducible per-cell
/// randomness in the haptic step: friction grains (§6.2) and texture lattices (§6.3).
/// Header-only, allocation-free.

#include <cstdint>

namespace lap::haptics {

[[nodiscard]] constexpr uint32_t hash32(uint32_t x) {
  x ^= x >> 16U;
  x *= 0x7feb352dU;
  x ^= x >> 15U;
  x *= 0x846ca68bU;
  x ^= x >> 16U;
  return x;
}

}  // namespace lap::haptics
