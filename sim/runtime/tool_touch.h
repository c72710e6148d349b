#pragma once
/// \file
/// What one tool touched and held on one haptic tick, as the session's recording keeps it
/// (issue 24: "every haptic tick's … contacts per organ, grasp state"; thesis §7.4: "record and
/// measure the forces applied by surgeons"). Per organ the tool touched: how many of its contacts
/// were on it and the magnitude of the tool's summed push on it; and whether its jaws held the
/// catheter or the duct in the model snapshot the tick read.
///
/// It makes a recording say what the trainee did without a replay, and lets a replay check
/// itself tick by tick against the live session (session_replay.h: a replay that departs, after
/// an author's untracked tuning or with another build of the simulator, says at which tick).

#include <array>
#include <cstddef>
#include <cstdint>

namespace lap::sim {

struct ToolContact;

struct ToolTouch {
  /// Organs listed per tool and tick (a gripper's three segments on three organs is the most
  /// seen in the shipped scenarios); any beyond are counted in `organs`, not listed.
  static constexpr size_t kListedOrgans = 4;
  bool catheter_held = false;  ///< in this tool's jaws (models::GraspState::held)
  bool duct_held = false;      ///< the duct wall in its jaws (models::DuctGraspState::grasping)
  uint8_t organs = 0;    ///< distinct organs touched (at most 12: ToolModelInput::kMaxContacts)
  uint8_t contacts = 0;  ///< the tool's contacts, over all organs (at most 12)
  /// The first min(organs, kListedOrgans) entries: in the order the tool's contacts name them.
  std::array<uint16_t, kListedOrgans> organ{};           ///< the scene's organ index
  std::array<uint16_t, kListedOrgans> organ_contacts{};  ///< the tool's contacts on it
  std::array<float, kListedOrgans> force_n{};            ///< |Σ of those contacts' push| [N]

  [[nodiscard]] size_t listed() const { return organs < kListedOrgans ? organs : kListedOrgans; }
  bool operator==(const ToolTouch&) const = default;
};

/// The touch of a tool whose `count` contacts are `contacts`, holding what the flags say.
/// Real-time code: no allocation. Contacts past ToolModelInput::kMaxContacts, or on an organ
/// index outside 0 to 65535 (no scene has that many organs), are left out.
[[nodiscard]] ToolTouch tool_touch(const ToolContact* contacts, int32_t count, bool catheter_held,
                                   bool duct_held) noexcept;

}  // namespace lap::sim
