#include "sim/runtime/tool_touch.h"

#include <Eigen/Core>
#include <algorithm>
#include <limits>

#include "sim/runtime/tissue_world.h"

namespace lap::sim {

static_assert(ToolModelInput::kMaxContacts <= 255, "ToolTouch counts contacts in a uint8");

ToolTouch tool_touch(const ToolContact* contacts, int32_t count, bool catheter_held,
                     bool duct_held) noexcept {
  ToolTouch t;
  t.catheter_held = catheter_held;
  t.duct_held = duct_held;
  // Distinct organs in the order the contacts name them; each listed one's push summed as a
  // vector (two jaws squeezing an organ from either side push it little).
  std::array<int32_t, ToolModelInput::kMaxContacts> seen{};
  std::array<Eigen::Vector3d, ToolTouch::kListedOrgans> push{};
  push.fill(Eigen::Vector3d::Zero());
  int32_t distinct = 0;
  const int32_t n = std::clamp(count, 0, ToolModelInput::kMaxContacts);
  for (int32_t c = 0; c < n; ++c) {
    const ToolContact& tc = contacts[c];
    if (tc.organ < 0 || tc.organ > 0xFFFF) continue;  // what the record cannot name (see header)
    int32_t k = 0;
    while (k < distinct && seen[static_cast<size_t>(k)] != tc.organ) ++k;
    if (k == distinct) seen[static_cast<size_t>(distinct++)] = tc.organ;
    ++t.contacts;
    if (static_cast<size_t>(k) >= ToolTouch::kListedOrgans) continue;  // counted, not listed
    const auto slot = static_cast<size_t>(k);
    t.organ[slot] = static_cast<uint16_t>(tc.organ);
    ++t.organ_contacts[slot];
    push[slot] += tc.force_on_organ_W;
  }
  t.organs = static_cast<uint8_t>(distinct);
  // A push too large for a float, or not finite (the watchdog trips on it), is kept as the
  // largest float: the record stays one its reader takes.
  constexpr double kLargest = std::numeric_limits<float>::max();
  for (size_t k = 0; k < t.listed(); ++k) {
    const double f = push[k].norm();
    t.force_n[k] = static_cast<float>(f < kLargest ? f : kLargest);
  }
  return t;
}

}  // namespace lap::sim
