#include "sim/runtime/lockstep_order.h"

namespace lap::sim {

int64_t LockstepOrder::tick_lag() const noexcept {
  return steps_ - newest_[static_cast<size_t>(ticks_)];
}

int64_t LockstepOrder::step_lag() const noexcept {
  return (ticks_ - 1) - reads_[static_cast<size_t>(steps_)];
}

LockstepOrder::Next LockstepOrder::next() const noexcept {
  const auto ticks = static_cast<int64_t>(newest_.size());
  const auto steps = static_cast<int64_t>(reads_.size());
  const bool tick_ready = ticks_ < ticks && newest_[static_cast<size_t>(ticks_)] <= steps_;
  const bool step_ready = steps_ < steps && reads_[static_cast<size_t>(steps_)] < ticks_;
  if (tick_ready && step_ready) return tick_lag() >= step_lag() ? Next::kTick : Next::kStep;
  if (tick_ready) return Next::kTick;
  if (step_ready) return Next::kStep;
  return ticks_ == ticks ? Next::kDone : Next::kStuck;
}

}  // namespace lap::sim
