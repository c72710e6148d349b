#pragma once
/// \file
/// The order in which a replay runs a recorded session's haptic ticks and modelling steps so
/// that each reads, from the other loop, the very snapshot it read live (issue 24: a session run
/// in real time replays to the same state_hash).
///
/// Live, the two loops run in their own threads and each takes the other's newest snapshot
/// (triple buffers): which one it got depends on the threads' timing, and the recording says
/// (session_recorder.h: per tick the model snapshot read, per step the haptic tick read). The
/// replay runs both in one thread, each tick or step whole, keeping the last few snapshots of
/// each loop so that a tick can read a model snapshot older than the newest (the model stepped
/// while the tick ran, live) and a step a haptic snapshot older than the newest.
///
/// A tick may run once the newer of its reads exists (the model snapshot and the proxies'
/// surfaces, read one after the other live: a tick held up between the two reads them many steps
/// apart), a step once the tick it read has run. When both may, the one further behind what it
/// reads runs first (its lag: how many newer snapshots of the other loop exist already), so that
/// neither history grows: a loop held up live (a tick preempted while the model stepped on, a
/// 100 ms modelling step while the ticks went on) then needs two snapshots of the other, not one
/// per tick or step it was held up. The older read of the next tick is kept apart by the replay
/// (Session::run_scheduled) until that tick has run, however many steps come before it.

#include <cstdint>
#include <span>

namespace lap::sim {

class LockstepOrder {
 public:
  enum class Next : uint8_t {
    kTick,  ///< run tick ticks_done()
    kStep,  ///< run step steps_done()
    kDone,  ///< every tick has run, and every step whose tick exists
    kStuck  ///< a tick reads a step the recording does not have (it was cut or damaged)
  };

  /// Per tick, the model snapshots it read (ModelSnapshot::steps: 0 the initial one, n after
  /// step n-1; the oldest and newest of its reads); per step, the haptic tick it read (-1: the
  /// initial snapshot).
  LockstepOrder(std::span<const int64_t> tick_oldest_read,
                std::span<const int64_t> tick_newest_read, std::span<const int64_t> step_tick_read)
      : oldest_(tick_oldest_read), newest_(tick_newest_read), reads_(step_tick_read) {}

  /// What to run next; call ran() after running it.
  [[nodiscard]] Next next() const noexcept;
  void ran(Next what) noexcept {
    if (what == Next::kTick) ++ticks_;
    if (what == Next::kStep) ++steps_;
  }

  [[nodiscard]] int64_t ticks_done() const { return ticks_; }
  [[nodiscard]] int64_t steps_done() const { return steps_; }
  /// Before running tick ticks_done(): how many model snapshots back from the newest the newer
  /// of its reads is (0: the newest). Before running step steps_done(): the same for the haptic
  /// snapshot it reads.
  [[nodiscard]] int64_t tick_lag() const noexcept;
  [[nodiscard]] int64_t step_lag() const noexcept;
  /// The older read of tick ticks_done() (-1 once every tick has run): the snapshot to keep
  /// apart until it runs.
  [[nodiscard]] int64_t next_tick_oldest_read() const noexcept {
    return ticks_ < static_cast<int64_t>(oldest_.size()) ? oldest_[static_cast<size_t>(ticks_)]
                                                         : -1;
  }

 private:
  std::span<const int64_t> oldest_;
  std::span<const int64_t> newest_;
  std::span<const int64_t> reads_;
  int64_t ticks_ = 0;
  int64_t steps_ = 0;
};

}  // namespace lap::sim
