#pragma once
/// \file
/// A single-producer, single-consumer triple buffer: the writer publishes whole values, the
/// reader takes the newest published one. Neither side ever waits for the other (wait-free), so
/// the haptic thread can read what the UI or the modelling thread wrote, and publish to them,
/// without a lock (docs/architecture.md, "What crosses between threads, and how").
///
/// Three slots: the writer owns one, the reader owns one, and the third ("middle") holds the
/// newest published value. Publishing swaps the writer's slot with the middle; reading swaps the
/// reader's slot with the middle when something new was published. The swap is one atomic
/// exchange of a small word holding the middle slot's index and a "fresh" bit.

#include <array>
#include <atomic>
#include <cstdint>
#include <utility>

namespace lap::hardware {

template <typename T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  explicit TripleBuffer(const T& initial) : slots_{initial, initial, initial} {}

  /// Set-up only (no other thread may use the buffer): every slot set to `value`, nothing fresh.
  void reset(const T& value) {
    slots_ = {value, value, value};
    middle_.store(1, std::memory_order_relaxed);
    back_ = 0;
    front_ = 2;
  }

  /// Set-up only: the three slots given (for values that are not copied: each slot its own
  /// object, which the writer brings up to date in place), nothing fresh; the reader holds
  /// values[2] until the first publish().
  void reset(std::array<T, 3>&& values) {
    slots_ = std::move(values);
    middle_.store(1, std::memory_order_relaxed);
    back_ = 0;
    front_ = 2;
  }

  /// Writer: the slot to fill before publish(). Only the writer touches it.
  T& write_slot() { return slots_[back_]; }
  /// Writer: make the filled slot the newest value.
  void publish() {
    const uint8_t old =
        middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
  }
  void publish(const T& value) {
    write_slot() = value;
    publish();
  }

  /// Reader: takes the newest published value if there is one; true if it was new.
  bool update() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  /// Reader: the value taken by the last update().
  [[nodiscard]] const T& read() const { return slots_[front_]; }
  /// Reader: update(), then read().
  const T& latest() {
    update();
    return read();
  }

 private:
  static constexpr uint8_t kIndex = 0x3;
  static constexpr uint8_t kFresh = 0x4;
  std::array<T, 3> slots_{};
  alignas(64) std::atomic<uint8_t> middle_{1};
  alignas(64) uint8_t back_ = 0;   // writer's
  alignas(64) uint8_t front_ = 2;  // reader's
};

}  // namespace lap::hardware
