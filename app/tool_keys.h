#pragma once
/// \file
/// The keyboard's tool keys, where the operative field and the set-up page's test screen both
/// read them: J L along x, U O along y, I K along z, [ ] the jaws, , . the roll, each a quarter
/// as far with Shift (what a press does: hardware/tool_nudge.h). Help > Controls lists them.

#include <optional>

#include "hardware/tool_nudge.h"

namespace lap::app {

/// The tool key a Qt key code (Qt::Key) stands for, with Shift's variants (Shift+[ arrives as
/// { on a US layout); none for any other key.
[[nodiscard]] std::optional<hardware::ToolKey> tool_key(int qt_key);
/// Whether a key event's modifiers (Qt::KeyboardModifiers) ask for the fine step (Shift).
[[nodiscard]] bool fine_step(int qt_modifiers);

}  // namespace lap::app
