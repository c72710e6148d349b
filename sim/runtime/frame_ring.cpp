#include "sim/runtime/frame_ring.h"

#include <chrono>
#include <thread>

namespace lap::sim {

void FrameRing::reserve(size_t catheter_points, const std::vector<SurfaceDeformation>& organs) {
  slots_.assign(static_cast<size_t>(kSlots), RecordedFrame{});
  for (RecordedFrame& f : slots_) {
    f.catheter.assign(catheter_points, Eigen::Vector3d::Zero());
    f.organs = organs;
  }
}

RecordedFrame* FrameRing::begin_write(bool wait_for_room) noexcept {
  if (slots_.empty()) return nullptr;
  const int64_t n = published_.load(std::memory_order_relaxed);
  while (n - released_.load(std::memory_order_acquire) >= kSlots) {
    if (!wait_for_room || closed_.load(std::memory_order_acquire)) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return nullptr;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return &slots_[static_cast<size_t>(n % kSlots)];
}

void FrameRing::publish() noexcept {
  published_.store(published_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
}

}  // namespace lap::sim
