#pragma once
/// \file
/// The mouse on the operative field, Ctrl held (app/vtk_view.cpp), as nudges of the active
/// simulated tool (tool_nudge.h): one table of the gestures' scales, read by the view and by the
/// tests' mouse operator (tests/support/keyboard_operator.h).

#include <Eigen/Core>

#include "hardware/tool_nudge.h"

namespace lap::hardware {

// A left drag moves the handle in the view's plane, 0.2 mm a pixel (a 10 cm stroke across the
// picture in 500 pixels); the wheel moves it along the line of sight, 2 mm a notch as a key press,
// a quarter with Shift; a middle drag sideways turns the instrument about its shaft, 0.005 rad (0.3
// degrees) a pixel, a quarter turn in 300 pixels; a right drag opens the jaws upwards and closes
// them downwards, 0.005 rad a pixel, closed to fully open in 200 pixels. Estimates: fine enough to
// place the tip to a few tenths of a millimetre and set the jaws within a degree, quick enough to
// cross the field in one stroke.
inline constexpr double kMouseMetresPerPixel = 2e-4;
inline constexpr double kMouseWheelMetresPerNotch = kKeyStepM;
inline constexpr double kMouseRollRadPerPixel = 0.005;
inline constexpr double kMouseJawsRadPerPixel = 0.005;

/// A Ctrl+left drag of (dx_px, dy_px) pixels (y downwards, as the screen's) in a view whose right
/// and up directions are `right_W` and `up_W` (unit).
[[nodiscard]] ToolNudge mouse_drag_nudge(double dx_px, double dy_px, const Eigen::Vector3d& right_W,
                                         const Eigen::Vector3d& up_W);
/// Ctrl+wheel: `notches` turned (forward positive; Qt's 120 angle units each, fractions from a
/// fine wheel) along the line of sight `view_dir_W` (unit, into the picture: forward moves the
/// handle away from the viewer); `fine` (Shift) a quarter.
[[nodiscard]] ToolNudge mouse_wheel_nudge(double notches, const Eigen::Vector3d& view_dir_W,
                                          bool fine);
/// Ctrl+middle drag sideways: `dx_px` pixels to the right turn the instrument right-handed about
/// its shaft (handle → port).
[[nodiscard]] ToolNudge mouse_roll_nudge(double dx_px);
/// Ctrl+right drag: `dy_px` pixels downwards (the screen's y) close the jaws, upwards open them.
[[nodiscard]] ToolNudge mouse_jaws_nudge(double dy_px);

}  // namespace lap::hardware
