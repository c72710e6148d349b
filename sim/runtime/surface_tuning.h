#pragma once
/// \file
/// Live tuning of the organs' haptic surfaces (issue 26's authoring mode): an author moves a
/// slider and feels the change at the next haptic tick. Two parts:
///
/// - `SurfaceTuningMailbox`: a single-producer single-consumer ring of fixed capacity. The author's
///   thread posts "organ o now has these parameters"; the haptic thread takes every waiting
///   message at the start of its next tick. Wait-free on both sides, no allocation: the producer
///   writes the slot then publishes its index with a release store, the consumer reads the index
///   with an acquire load, copies the slot, then frees it with a release store of its own index
///   (Lamport's ring). A full ring refuses the post (the caller posts again later; a slider only
///   needs its latest value to arrive). A message may carry the haptic tick that posted it, for a
///   consumer that must take it at a point thread timing does not decide (take_until).
/// - `TunedSurfaces`: the haptic thread's own per-organ parameters and what they need — a copy of
///   each organ's friction model and a texture scaled in height — set up once from the session's
///   objects; `apply` writes them into the objects the proxies read, every tick after the
///   surfaces' copy is switched (which resets the shading pointers).
///
/// The haptic surface changes (force law §4, friction §6.2, shading §6.1 on/off, texture §6.3
/// height), and the tissue models follow the stiffness: each tool contact carries the k it was
/// rendered with to the modelling loop (ToolContact::stiffness_n_per_m: a local organ's dent
/// infers the tool's displacement as force / k), and the session forwards a tuned k to the
/// catheter's contacts through a second mailbox of this kind (haptic thread to modelling
/// thread; Session::forward_stiffness_to_model). The rest keeps what it was built with.
///
/// What each tick took is recorded (session_recorder.h, TuningLog: the organs' parameters after
/// it), and a replay sets the same values at the same ticks (TunedSurfaces::set), so that a
/// tuned session replays to its own state.

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "haptics/friction.h"
#include "haptics/haptic_object.h"
#include "haptics/height_field.h"

namespace lap::sim {

/// An organ's haptic surface as the author tunes it.
struct SurfaceParameters {
  double stiffness_n_per_m = 0.0;  ///< the contact spring k (§4)
  double damping_n_s_per_m = 0.0;  ///< the contact damper b
  double friction_static = 0.0;    ///< μs (§6.2); 0: frictionless
  double friction_dynamic = 0.0;   ///< μd, at most μs
  bool shading = false;            ///< force shading (§6.1), where the organ has normals
  /// The texture's height relative to the scenario's (§6.3): 1 as loaded, 0 flat; an organ
  /// without a texture ignores it.
  double texture_scale = 1.0;
};

/// One producer thread posts, one consumer thread takes (see the file comment): the author's
/// thread to the haptic thread, or the haptic thread to the modelling thread.
class SurfaceTuningMailbox {
 public:
  static constexpr uint64_t kCapacity = 64;
  /// Producer: queue organ `organ`'s new parameters; false when the ring is full.
  /// `tick`: the haptic tick posting it (take_until), else 0.
  bool post(int32_t organ, const SurfaceParameters& p, int64_t tick = 0) noexcept {
    const uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= kCapacity) return false;
    ring_[head % kCapacity] = {organ, tick, p};
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  /// Consumer: calls f(organ, parameters) for every waiting message, oldest first; returns how
  /// many.
  template <class F>
  int32_t take(F&& f) noexcept {
    uint64_t tail = tail_.load(std::memory_order_relaxed);
    const uint64_t head = head_.load(std::memory_order_acquire);
    int32_t n = 0;
    for (; tail != head; ++tail, ++n) {
      const Message& m = ring_[tail % kCapacity];
      f(m.organ, m.parameters);
    }
    tail_.store(tail, std::memory_order_release);
    return n;
  }
  /// Consumer: as take(), for the waiting messages posted at ticks up to `tick` only, oldest
  /// first (a producer posts at ticks that do not decrease): the modelling step that read haptic
  /// tick t's snapshot takes what ticks up to t posted, all of which were published before that
  /// snapshot, and nothing a later tick may or may not have posted yet.
  template <class F>
  int32_t take_until(int64_t tick, F&& f) noexcept {
    uint64_t tail = tail_.load(std::memory_order_relaxed);
    const uint64_t head = head_.load(std::memory_order_acquire);
    int32_t n = 0;
    for (; tail != head && ring_[tail % kCapacity].tick <= tick; ++tail, ++n) {
      const Message& m = ring_[tail % kCapacity];
      f(m.organ, m.parameters);
    }
    tail_.store(tail, std::memory_order_release);
    return n;
  }
  /// Messages posted so far (producer's count; any thread).
  [[nodiscard]] uint64_t posted() const noexcept { return head_.load(std::memory_order_acquire); }
  /// Messages taken so far (any thread).
  [[nodiscard]] uint64_t taken() const noexcept { return tail_.load(std::memory_order_acquire); }

 private:
  struct Message {
    int32_t organ = -1;
    int64_t tick = 0;
    SurfaceParameters parameters;
  };
  std::array<Message, kCapacity> ring_{};
  std::atomic<uint64_t> head_{0};
  std::atomic<uint64_t> tail_{0};
};

/// A height field `scale` times as high as another (which must outlive it): h' = s h, ∇h' = s ∇h.
class ScaledHeightField final : public haptics::HeightField {
 public:
  explicit ScaledHeightField(const haptics::HeightField* base) : base_(base) {}
  [[nodiscard]] haptics::HeightSample sample(const Eigen::Vector3d& p) const noexcept override {
    haptics::HeightSample s = base_->sample(p);
    s.height_m *= scale_;
    s.gradient *= scale_;
    return s;
  }
  [[nodiscard]] double max_height_m() const noexcept override {
    return scale_ * base_->max_height_m();
  }
  void set_scale(double s) noexcept { scale_ = s; }

 private:
  const haptics::HeightField* base_;
  double scale_ = 1.0;
};

/// The haptic thread's tuned surfaces (see the file comment).
class TunedSurfaces {
 public:
  /// Setup: each organ's parameters as `objects` have them (the session's objects, pointed at
  /// their surfaces). Allocates.
  void init(std::span<const haptics::HapticObject> objects);
  /// Haptic thread: takes the mailbox's messages, each as set() does; true when any organ's
  /// parameters were set. No allocation.
  bool take(SurfaceTuningMailbox* mailbox) noexcept;
  /// Haptic thread: organ o's parameters from now on; false, and nothing changed, for an organ
  /// out of range or a value not finite or negative. μd is capped at μs, shading needs normals:
  /// setting what parameters() then gives changes nothing (a replay sets the recorded values).
  bool set(int32_t o, const SurfaceParameters& p) noexcept;
  /// Whether organ o's parameters were set since the last clear_changed() (haptic thread).
  [[nodiscard]] bool changed(int32_t o) const { return organs_[static_cast<size_t>(o)].changed; }
  void clear_changed() noexcept;
  /// Haptic thread: writes every tuned organ's parameters into `objects` (the same organs as at
  /// init). No allocation.
  void apply(std::span<haptics::HapticObject> objects) noexcept;
  [[nodiscard]] int32_t organ_count() const { return static_cast<int32_t>(organs_.size()); }
  /// Organ o's parameters as the haptic loop renders them (haptic thread; others: see
  /// Session::surface_parameters).
  [[nodiscard]] const SurfaceParameters& parameters(int32_t o) const {
    return organs_[static_cast<size_t>(o)].now;
  }
  /// Whether organ o can have force shading switched on (it has normals) / a texture to scale.
  [[nodiscard]] bool can_shade(int32_t o) const {
    return organs_[static_cast<size_t>(o)].normals != nullptr;
  }
  [[nodiscard]] bool has_texture(int32_t o) const {
    return organs_[static_cast<size_t>(o)].texture != nullptr;
  }

 private:
  struct Organ {
    SurfaceParameters now;
    bool tuned = false;    ///< apply() leaves untouched organs as the model set them
    bool changed = false;  ///< set since clear_changed()
    /// The friction as the scenario has it (k_s, k_d, map), and the one rendered.
    haptics::FrictionModel base_friction;
    bool had_friction = false;
    double base_stiffness_n_per_m = 0.0;
    haptics::FrictionModel friction;
    const haptics::ShadingNormals* normals = nullptr;  ///< the current copy's; null: none
    std::unique_ptr<ScaledHeightField> texture;        ///< null: the organ has none
  };
  std::vector<Organ> organs_;
  int32_t changed_count_ = 0;
};

}  // namespace lap::sim
