#pragma once
/// \file
/// Where a replay departs from the session it replays, by what each tool touched and held on
/// each tick (tool_touch.h; the recording keeps both since LAPREC03). A replay of the same build
/// on the same scenario gives every tick's touch to the bit; one that does not — an author's live
/// tuning the recording does not hold, another build of the simulator, a recording altered after
/// its checksums — is named at its first differing tick, so that a reviewer knows from when the
/// replay's figures are no longer the session's.

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sim/runtime/session_recorder.h"

namespace lap::sim {

/// "held the catheter, touched Gallbladder (2 contacts, 1.25 N), 1 more organ"; "touched
/// nothing" (organ names by the scene's index; an index past them is "organ N").
[[nodiscard]] std::string describe_touch(const ToolTouch& touch,
                                         const std::vector<std::string>& organ_names);

/// The note for the first tick on which `replayed` (Session::tick_log) differs from `recorded`
/// (each tick's ToolTouch per tool, in tick order from 0), over the ticks both have; none when
/// they agree. `haptic_rate_hz` gives the tick's time.
[[nodiscard]] std::optional<std::string> touch_departure(
    std::span<const std::array<ToolTouch, 2>> recorded, std::span<const TickLog> replayed,
    const std::vector<std::string>& organ_names, double haptic_rate_hz);

}  // namespace lap::sim
