// One libFuzzer executable per target: fuzz_<name>, built by the `fuzz` preset with clang's
// -fsanitize=fuzzer,address,undefined. LAP_FUZZ_TARGET names the target (fuzz_targets.cpp).
#include <cstdint>
#include <cstdlib>
#include <span>

#include "tests/fuzz/fuzz_targets.h"

namespace {
const lap::fuzz::FuzzTarget* target() {
  static const lap::fuzz::FuzzTarget* t = lap::fuzz::find_fuzz_target(LAP_FUZZ_TARGET);
  if (t == nullptr) std::abort();
  return t;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  target()->run(std::span<const uint8_t>(data, size));
  return 0;
}
