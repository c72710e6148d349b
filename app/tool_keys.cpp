#include "app/tool_keys.h"

#include <Qt>

namespace lap::app {

std::optional<hardware::ToolKey> tool_key(int qt_key, int qt_modifiers) {
  using hardware::ToolKey;
  if (fine_step(qt_modifiers)) {
    switch (qt_key) {
      case Qt::Key_BraceLeft:  // Shift+[ on a US layout
        return ToolKey::kClose;
      case Qt::Key_BraceRight:
        return ToolKey::kOpen;
      case Qt::Key_Less:  // Shift+,
        return ToolKey::kRollMinus;
      case Qt::Key_Greater:
        return ToolKey::kRollPlus;
      default:
        break;
    }
  }
  switch (qt_key) {
    case Qt::Key_J:
      return ToolKey::kXMinus;
    case Qt::Key_L:
      return ToolKey::kXPlus;
    case Qt::Key_U:
      return ToolKey::kYPlus;
    case Qt::Key_O:
      return ToolKey::kYMinus;
    case Qt::Key_I:
      return ToolKey::kZMinus;
    case Qt::Key_K:
      return ToolKey::kZPlus;
    case Qt::Key_BracketLeft:
      return ToolKey::kClose;
    case Qt::Key_BracketRight:
      return ToolKey::kOpen;
    case Qt::Key_Comma:
      return ToolKey::kRollMinus;
    case Qt::Key_Period:
      return ToolKey::kRollPlus;
    default:
      return std::nullopt;
  }
}

bool fine_step(int qt_modifiers) { return (qt_modifiers & Qt::ShiftModifier) != 0; }

}  // namespace lap::app
