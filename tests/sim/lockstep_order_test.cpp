// The order in which a replay runs a recorded session's ticks and steps (sim/runtime/
// lockstep_order.h), against a brute-force reference: two loops interleaved at random, as two
// threads would be (bursts, a loop held up for a long while mid-tick or mid-step), each taking
// the other's newest snapshot through a triple buffer. Their reads are recorded as the session
// recording does; a replay on one thread in LockstepOrder's order, keeping only the last
// kLockstepHistory snapshots of each loop, must end in the same state, bit for bit.

#include "sim/runtime/lockstep_order.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "sim/runtime/session.h"

namespace lap::sim {
namespace {

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
  return h * 0x100000001B3ULL;
}

constexpr uint64_t kHapticSeed = 11;
constexpr uint64_t kModelSeed = 23;

// What the two loops did live: each tick's reads (model snapshot, then surfaces: both the
// number of steps behind them) and each step's (the haptic tick), and each loop's state after
// every tick or step. A tick's state mixes in the model states it read; a step's, the haptic
// state it read.
struct LiveRun {
  std::vector<int64_t> tick_model_read, tick_surface_read, step_tick_read;
  std::vector<uint64_t> haptic_state;  ///< after tick t
  std::vector<uint64_t> model_state;   ///< after n steps (n = 0: the initial state)
};

// The threads' atomic actions. A tick: read the model snapshot, read the surfaces, publish. A
// step: read the haptic snapshot, publish the surfaces, publish the model snapshot. Which loop
// acts next is random, in bursts; now and then one loop is held up for `hold` actions of the
// other, at whatever point of its tick or step it is.
LiveRun run_live(uint32_t seed, int64_t ticks, int hold) {
  std::mt19937 rng(seed);
  LiveRun r;
  r.model_state.push_back(kModelSeed);
  int64_t published_surfaces = 0;  // steps behind the newest surfaces
  int64_t published_model = 0;     // steps behind the newest model snapshot
  int64_t published_tick = -1;
  int haptic_phase = 0, model_phase = 0;
  int64_t tick_model = 0, tick_surfaces = 0, step_read = -1;
  uint64_t step_state = 0;
  const auto haptic_state = [&](int64_t t) { return t < 0 ? kHapticSeed : r.haptic_state[t]; };
  while (static_cast<int64_t>(r.haptic_state.size()) < ticks) {
    const bool haptic = rng() % 2 == 0;
    int burst = 1 + static_cast<int>(rng() % 4);
    if (rng() % 50 == 0) burst = hold;
    for (int b = 0; b < burst && static_cast<int64_t>(r.haptic_state.size()) < ticks; ++b) {
      if (haptic) {
        if (haptic_phase == 0) tick_model = published_model;
        if (haptic_phase == 1) tick_surfaces = published_surfaces;
        if (haptic_phase == 2) {
          const auto t = static_cast<int64_t>(r.haptic_state.size());
          r.tick_model_read.push_back(tick_model);
          r.tick_surface_read.push_back(tick_surfaces);
          r.haptic_state.push_back(mix(mix(haptic_state(t - 1), r.model_state[tick_model]),
                                       r.model_state[tick_surfaces] * 3));
          published_tick = t;
        }
        haptic_phase = (haptic_phase + 1) % 3;
      } else {
        if (model_phase == 0) {
          step_read = published_tick;
          step_state = mix(r.model_state.back(), haptic_state(step_read));
        }
        if (model_phase == 1) {
          r.step_tick_read.push_back(step_read);
          r.model_state.push_back(step_state);
          published_surfaces = static_cast<int64_t>(r.model_state.size()) - 1;
        }
        if (model_phase == 2) published_model = static_cast<int64_t>(r.model_state.size()) - 1;
        model_phase = (model_phase + 1) % 3;
      }
    }
  }
  return r;
}

struct Replayed {
  uint64_t haptic = 0;
  uint64_t model = 0;
  int64_t ticks = 0;
  int64_t steps = 0;
  int64_t largest_lag = 0;       ///< of the newer read of a tick, or a step's read
  int64_t reads_kept_apart = 0;  ///< ticks' older reads found only where they were kept apart
  LockstepOrder::Next end = LockstepOrder::Next::kDone;
};

// A snapshot as the replay keeps it: which one it is (a tick, or a number of steps), its state.
struct Kept {
  int64_t id = -1;
  uint64_t state = 0;
};

// The replay: one thread, LockstepOrder's order, each loop's last n snapshots, and the next
// tick's older read kept apart, as Session::run_scheduled keeps them; a read of a snapshot no
// longer kept stops it.
Replayed replay(const LiveRun& live, std::vector<int64_t> step_reads) {
  constexpr int64_t n = Session::kLockstepHistory;
  std::vector<int64_t> oldest, newest;
  for (size_t t = 0; t < live.tick_model_read.size(); ++t) {
    oldest.push_back(std::min(live.tick_model_read[t], live.tick_surface_read[t]));
    newest.push_back(std::max(live.tick_model_read[t], live.tick_surface_read[t]));
  }
  Replayed out;
  std::vector<Kept> haptic_ring(n, {-1, kHapticSeed}), model_ring(n, {0, kModelSeed});
  Kept model_apart;
  const auto slot = [](int64_t i) { return static_cast<size_t>(((i % n) + n) % n); };
  const auto model_read = [&](int64_t steps, uint64_t* state) {
    const bool in_ring = model_ring[slot(steps)].id == steps;
    const Kept& k = in_ring ? model_ring[slot(steps)] : model_apart;
    *state = k.state;
    out.reads_kept_apart += in_ring ? 0 : 1;
    return k.id == steps;
  };
  LockstepOrder order(oldest, newest, step_reads);
  uint64_t haptic = kHapticSeed, model = kModelSeed;
  for (auto next = order.next();
       next == LockstepOrder::Next::kTick || next == LockstepOrder::Next::kStep;
       next = order.next()) {
    const int64_t t = order.ticks_done(), k = order.steps_done();
    out.largest_lag = std::max(
        out.largest_lag, next == LockstepOrder::Next::kTick ? order.tick_lag() : order.step_lag());
    if (next == LockstepOrder::Next::kTick) {
      const auto tt = static_cast<size_t>(t);
      uint64_t m = 0, u = 0;
      if (!model_read(live.tick_model_read[tt], &m) ||
          !model_read(live.tick_surface_read[tt], &u)) {
        break;
      }
      haptic = mix(mix(haptic, m), u * 3);
      haptic_ring[slot(t + 1)] = {t, haptic};
    } else {
      const Kept& h = haptic_ring[slot(step_reads[static_cast<size_t>(k)] + 1)];
      if (h.id != step_reads[static_cast<size_t>(k)]) break;
      model = mix(model, h.state);
      Kept& evicted = model_ring[slot(k + 1)];
      if (evicted.id == order.next_tick_oldest_read()) model_apart = evicted;
      evicted = {k + 1, model};
    }
    order.ran(next);
  }
  out.haptic = haptic;
  out.model = model;
  out.ticks = order.ticks_done();
  out.steps = order.steps_done();
  out.end = order.next();
  return out;
}

TEST(LockstepOrder, ReplaysRandomInterleavingsOfTheTwoLoopsToTheSameState) {
  int64_t largest_lag = 0, reads_kept_apart = 0;
  for (uint32_t seed = 1; seed <= 200; ++seed) {
    const int hold = seed % 2 == 0 ? 40 : 400;  // a loop held up for 40 or 400 of the other's
    const LiveRun live = run_live(seed, 3000, hold);
    const Replayed r = replay(live, live.step_tick_read);
    ASSERT_EQ(r.end, LockstepOrder::Next::kDone) << "seed " << seed;
    ASSERT_EQ(r.ticks, 3000) << "seed " << seed;
    ASSERT_EQ(r.steps, static_cast<int64_t>(live.step_tick_read.size())) << "seed " << seed;
    ASSERT_EQ(r.haptic, live.haptic_state.back()) << "seed " << seed;
    ASSERT_EQ(r.model, live.model_state.back()) << "seed " << seed;
    largest_lag = std::max(largest_lag, r.largest_lag);
    reads_kept_apart += r.reads_kept_apart;
  }
  // Neither loop ever reads further back than the history a replay keeps (measured: 1).
  EXPECT_LT(largest_lag, Session::kLockstepHistory);
  // And the histories are needed: some tick or step read a snapshot older than the newest; and
  // some tick, held up between its two reads, read its model snapshot many steps before its
  // surfaces, from where the replay kept it apart.
  EXPECT_GE(largest_lag, 1);
  EXPECT_GT(reads_kept_apart, 0);
}

// The reference's reads are what makes the replay right: replaying with the steps reading
// one tick off gives another state (the test above could not pass by accident).
TEST(LockstepOrder, OtherReadsGiveAnotherState) {
  const LiveRun live = run_live(7, 3000, 400);
  std::vector<int64_t> reads = live.step_tick_read;
  bool moved = false;
  for (size_t k = 1; k < reads.size() && !moved; ++k) {
    if (reads[k] > reads[k - 1] + 1) {
      --reads[k];
      moved = true;
    }
  }
  ASSERT_TRUE(moved);
  const Replayed r = replay(live, reads);
  EXPECT_NE(r.model, live.model_state.back());
}

// A recording whose steps end early (cut off, or a damaged chunk): the replay runs every tick
// whose reads it has and says it is stuck at the first that read a step it does not have.
TEST(LockstepOrder, StopsAtTheFirstTickThatReadAStepNotRecorded) {
  const LiveRun live = run_live(3, 3000, 40);
  const size_t kept = live.step_tick_read.size() / 2;
  const std::vector<int64_t> reads(live.step_tick_read.begin(),
                                   live.step_tick_read.begin() + static_cast<int64_t>(kept));
  const Replayed r = replay(live, reads);
  EXPECT_EQ(r.end, LockstepOrder::Next::kStuck);
  EXPECT_EQ(r.steps, static_cast<int64_t>(kept));
  ASSERT_LT(r.ticks, 3000);
  const auto t = static_cast<size_t>(r.ticks);
  EXPECT_GT(std::max(live.tick_model_read[t], live.tick_surface_read[t]),
            static_cast<int64_t>(kept));
  // Every tick before it read steps the recording has.
  for (size_t u = 0; u < t; ++u) EXPECT_LE(live.tick_model_read[u], static_cast<int64_t>(kept));
}

// No ticks and no steps: nothing to run.
TEST(LockstepOrder, AnEmptyRecordingIsDoneAtOnce) {
  const LockstepOrder order({}, {}, {});
  EXPECT_EQ(order.next(), LockstepOrder::Next::kDone);
}

}  // namespace
}  // namespace lap::sim
