#pragma once
/// \file
/// What a recording says of an author's live surface tunings (issue 26's authoring mode, the
/// recording's tunings chunk since LAPREC04), for a replay's notes: that the session was tuned and
/// the replay renders the recorded values at the ticks that took them; a tuned tick whose values
/// the recording does not hold (a damaged chunk, the room for tunings exhausted, a LAPREC03
/// file), from which on the replay renders other surfaces than the session did; a tuning naming
/// an organ the scenario does not have.

#include <span>
#include <string>
#include <vector>

#include "sim/runtime/session_recorder.h"

namespace lap::sim {

/// The notes for ticks `ticks` (in tick order from 0) and the tunings read with them (in tick
/// order), of a recording of format `version` (recording_reader.h), replayed on a scene of
/// `organ_count` organs at `haptic_rate_hz`; none for a session nobody tuned.
[[nodiscard]] std::vector<std::string> recorded_tuning_notes(std::span<const TickLog> ticks,
                                                             std::span<const TuningLog> tunings,
                                                             int version, int32_t organ_count,
                                                             double haptic_rate_hz);

}  // namespace lap::sim
