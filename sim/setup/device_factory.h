#pragma once
/// \file
/// Builds the device a `run --left DEV --right DEV` argument names (hardware/device_spec.h) for
/// one tool of a loaded scene: scripted and replay devices read their files here (set-up), a
/// simulated device starts with the tool 10 cm inside its trocar, pointing at the scene.

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
/// target organ (else the scene's centre): for simulated devices and generated scripts.
[[nodiscard]] Eigen::Vector3d default_handle_position(const Scene& scene, int side,
                                                      double inside_m);

}  // namespace lap::sim
