#include "sim/report/recorded_tunings.h"

#include <algorithm>
#include <cstdio>

namespace lap::sim {

namespace {

std::string tick_at(int64_t tick, double haptic_rate_hz) {
  char t[48];
  std::snprintf(t, sizeof(t), " (%.3f s)", static_cast<double>(tick) / haptic_rate_hz);
  return "tick " + std::to_string(tick) + t;
}

}  // namespace

std::vector<std::string> recorded_tuning_notes(std::span<const TickLog> ticks,
                                               std::span<const TuningLog> tunings, int version,
                                               int32_t organ_count, double haptic_rate_hz) {
  std::vector<std::string> notes;
  const auto first_tuned =
      std::find_if(ticks.begin(), ticks.end(), [](const TickLog& t) { return t.tuned; });
  if (first_tuned == ticks.end() && tunings.empty()) return notes;
  if (version < 4) {
    notes.push_back("an author tuned organ surfaces live from tick " +
                    std::to_string(first_tuned->tick) +
                    " on; the recording does not hold the values, so the replay renders the "
                    "scenario's and its figures may differ from the session's");
    return notes;
  }
  const int64_t from = first_tuned != ticks.end() ? first_tuned->tick : tunings.front().tick;
  if (tunings.empty()) {
    notes.push_back("an author tuned organ surfaces live from " + tick_at(from, haptic_rate_hz) +
                    " on, and the recording holds none of the values (its tunings are damaged or "
                    "were not recorded): the replay renders the scenario's and its figures may "
                    "differ from the session's");
    return notes;
  }
  notes.push_back("an author tuned organ surfaces live (" + std::to_string(tunings.size()) +
                  " changes, from " + tick_at(from, haptic_rate_hz) +
                  " on): the replay renders the recorded values from the ticks that took them");
  // A tuned tick has a record per organ it changed; one without any was not recorded.
  const auto missing = std::find_if(first_tuned, ticks.end(), [&](const TickLog& t) {
    if (!t.tuned) return false;
    const auto at = std::lower_bound(tunings.begin(), tunings.end(), t.tick,
                                     [](const TuningLog& r, int64_t k) { return r.tick < k; });
    return at == tunings.end() || at->tick != t.tick;
  });
  if (missing != ticks.end()) {
    notes.push_back("the tuning taken at " + tick_at(missing->tick, haptic_rate_hz) +
                    " is not in the recording: from there on the replay may render other "
                    "surfaces than the session did");
  }
  const auto stranger = std::find_if(tunings.begin(), tunings.end(),
                                     [&](const TuningLog& r) { return r.organ >= organ_count; });
  if (stranger != tunings.end()) {
    notes.push_back("the tuning taken at " + tick_at(stranger->tick, haptic_rate_hz) +
                    " names organ " + std::to_string(stranger->organ) + ", and the scenario has " +
                    std::to_string(organ_count) + ": it is not replayed");
  }
  return notes;
}

}  // namespace lap::sim
