#pragma once
/// \file
/// Builds the device a `run --left DEV --right DEV` argument names (hardware/device_spec.h) for
/// one tool of a loaded scene: scripted and replay devices read their files here (set-up), a
/// simulated device starts with the tool at its home (home_handle_position), and a PHANToM's
/// origin is there.

#include <memory>
#include <string>

#include "core/result.h"
#include "hardware/device_spec.h"
#include "hardware/haptic_device.h"
#include "sim/setup/scene.h"

namespace lap::sim {

/// side: 0 left, 1 right. The diagnostic names the file or what to install on failure.
[[nodiscard]] Result<std::unique_ptr<hardware::HapticDevice>> make_device(
    const hardware::DeviceSpec& spec, const Scene& scene, int side);

/// Where the handle is when the tool's tip is `inside_m` into its trocar, pointing at the task's
/// target organ (else the scene's centre): for generated scripts and tests.
[[nodiscard]] Eigen::Vector3d default_handle_position(const Scene& scene, int side,
                                                      double inside_m);

/// Where a tool starts (a simulated device's home, the keyboard's H, a PHANToM's origin):
/// pointing at the task's target like default_handle_position, 10 cm into its trocar, or deeper,
/// 2 cm past where its tip comes into the laparoscope's picture (CameraPicture of the
/// scenario's camera), so the resident starts with both instruments in view: the task counts
/// an instrument out of view from the first tick. At most 60 % of the way to the target.
[[nodiscard]] Eigen::Vector3d home_handle_position(const Scene& scene, int side);

}  // namespace lap::sim
