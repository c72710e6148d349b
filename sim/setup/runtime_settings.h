#pragma once
/// \file
/// How a session runs, as its caller chooses (the command line, the app, a test): the loops'
/// rates, lockstep or real time, its length, the watchdog's and the scheduler's settings.

#include <cstdint>

namespace lap::sim {

struct RuntimeSettings {
  double haptic_rate_hz = 1000.0;
  double model_rate_hz = 200.0;
  bool fast = false;           ///< lockstep, as fast as possible, deterministic
  double duration_s = 10.0;    ///< the session ends here, or when every device has finished
  double resume_ramp_s = 0.5;  ///< forces ramp from 0 to full over this after resume()
  double record_s = -1.0;      ///< inputs kept for this long (reserved at start); < 0: the duration
  /// The session ends when the scenario's task ends (success or failure; sim/runtime/
  /// task_engine.h), as `laptrainer-cli run` wants; the app keeps the trainee's session going.
  bool end_with_task = true;
  /// The trainee's dominant hand (0 left, 1 right), for the handedness metrics.
  int32_t dominant_tool = 1;
  /// The watchdog's timing (docs/architecture.md, "The watchdog"). A desktop kernel starts a
  /// tick more than 2 ms late now and then (an idle real-time sleep loop shows the same), and
  /// pausing the session for each would interrupt a trainee several times a minute. So:
  /// - a *late tick* starts more than `overrun_periods` periods late: the device has held its
  ///   last command too long, so this tick sends zero force, torque and squeeze, and the forces
  ///   ramp back by themselves over `late_tick_ramp_s`; counted (`late_ticks`), no pause, no event;
  /// - a *stall* starts at least `stall_s` late (no tick for 20 ms or more): too long to pass
  ///   over, so the session pauses as for a fault (forces zero until resume()).
  double overrun_periods = 2.0;
  double stall_s = 0.020;
  /// Short enough that a single late tick goes unnoticed: the forces are back within 100 ms
  /// (Session::create refuses a longer ramp); long enough that they come back as a ramp, not as
  /// a step the hand feels as a knock. A slower ramp under way (a resume) keeps its pace.
  double late_tick_ramp_s = 0.05;
  /// The haptic loop sleeps until this long before its deadline, then spins: a thread woken
  /// from a kernel sleep on these machines is now and then 100-300 µs late, which a 200 µs
  /// spin absorbs (at the cost of a fifth of a core while the loop runs at 1 kHz).
  int64_t spin_ns = 200000;
  /// The spin instead where the haptic thread shares its processor with the rest of the process
  /// (isolate_haptic_processor on, but keep_others_off_haptic_processor false: two processors
  /// and SCHED_FIFO). There the renderer needs the spin's fifth of a core: with Mesa's software
  /// renderer on the 2-core VM, the hardest patient drew 3-3.5 frames/s more with 50 µs than
  /// with 200 µs, and the haptic loop's p99.9 lateness was 0.6-1.2 ms with either, that is the
  /// VM's, not the kernel sleep's (29 Nov 2026, docs/benchmarks.md).
  int64_t shared_processor_spin_ns = 50000;
  bool realtime_priority = true;  ///< ask for SCHED_FIFO and mlockall
  /// Pin the haptic thread to a processor (the last one) and, where that helps
  /// (keep_others_off_haptic_processor: three processors or more, or no SCHED_FIFO), keep every
  /// other thread of the process, the renderer's too, off it while the loops run. Off by
  /// default: on the 2-core VM measured, keeping the processor helped while software rendering
  /// ran (28 Nov, since then only with three processors or more) and hurt headless
  /// (docs/benchmarks.md); the app turns it on.
  bool isolate_haptic_processor = false;
  /// The passivity observer and controller at each tool's handle (hardware/passivity_controller.h).
  /// Off only to show, in tests, what it guards against.
  bool passivity_control = true;
};

}  // namespace lap::sim
