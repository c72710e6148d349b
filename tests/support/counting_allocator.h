#pragma once
/// \file
/// Counts heap allocations while armed (Drake's LimitMalloc idea): link counting_allocator.cpp
/// into a test binary and wrap the code under test in an AllocationCounter.

#include <cstdint>

namespace lap::test {

/// Counts calls to operator new in this thread's program while alive.
class AllocationCounter {
 public:
  AllocationCounter();
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  [[nodiscard]] int64_t count() const;
};

}  // namespace lap::test
