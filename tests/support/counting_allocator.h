#pragma once
/// \file
/// Counts heap allocations while armed (Drake's LimitMalloc idea): link counting_allocator.cpp
/// into a test binary and wrap the code under test in an AllocationCounter.

#include <cstdint>

namespace lap::test {

/// Counts calls to operator new in this thread's program while alive; with kThisThread, only
/// those of the thread that made the counter (a loop's, while a writer thread allocates).
class AllocationCounter {
 public:
  enum class Scope { kAllThreads, kThisThread };
  explicit AllocationCounter(Scope scope = Scope::kAllThreads);
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  [[nodiscard]] int64_t count() const;
};

}  // namespace lap::test
