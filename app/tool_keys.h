#pragma once
/// \file
/// The keyboard's tool keys, where the operative field and the set-up page's test screen both
/// read them: J L along x, U O along y, I K along z, [ ] the jaws, , . the roll, each a quarter
/// as far with Shift (what a press does: hardware/tool_nudge.h). Help > Controls lists them.

#include <optional>

#include "hardware/tool_nudge.h"

namespace lap::app {

/// The tool key a Qt key code (Qt::Key) with its modifiers (Qt::KeyboardModifiers) stands for;
/// none for any other key. With Shift, the characters Shift makes of [ ] , . on a US layout
/// ({ } < >) count as those keys; without Shift they are not tool keys (an ISO layout's own
/// < key would otherwise roll one way 5 degrees and, shifted, the other way a quarter of that).
[[nodiscard]] std::optional<hardware::ToolKey> tool_key(int qt_key, int qt_modifiers);
/// Whether a key event's modifiers (Qt::KeyboardModifiers) ask for the fine step (Shift).
[[nodiscard]] bool fine_step(int qt_modifiers);

}  // namespace lap::app
