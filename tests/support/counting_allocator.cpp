#include "tests/support/counting_allocator.h"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {
std::atomic<bool> g_armed{false};
std::atomic<int64_t> g_count{0};
std::atomic<bool> g_this_thread_only{false};
thread_local bool t_counted = false;  // the thread whose counter asked for kThisThread

bool counting() {
  return g_armed.load(std::memory_order_relaxed) &&
         (!g_this_thread_only.load(std::memory_order_relaxed) || t_counted);
}

void* counted_alloc(std::size_t size) {
  if (counting()) g_count.fetch_add(1, std::memory_order_relaxed);
  void* p = std::malloc(size == 0 ? 1 : size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t size) { return counted_alloc(size); }
void* operator new[](std::size_t size) { return counted_alloc(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (counting()) g_count.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace lap::test {

AllocationCounter::AllocationCounter(Scope scope) {
  g_count.store(0);
  t_counted = scope == Scope::kThisThread;
  g_this_thread_only.store(scope == Scope::kThisThread);
  g_armed.store(true);
}
AllocationCounter::~AllocationCounter() {
  g_armed.store(false);
  g_this_thread_only.store(false);
  t_counted = false;
}
int64_t AllocationCounter::count() const { return g_count.load(); }

}  // namespace lap::test
