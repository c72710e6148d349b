#include "sim/setup/device_factory.h"

#include <algorithm>

#include "hardware/device_recording.h"
#include "hardware/libusb_transport.h"
#include "hardware/open_haptics_api.h"
#include "hardware/phantom_device.h"
#include "hardware/replay_device.h"
#include "hardware/scripted_device.h"
#include "hardware/simulated_device.h"
#include "hardware/usb_gripper.h"
#include "sim/setup/camera_picture.h"

namespace lap::sim {

Eigen::Vector3d default_handle_position(const Scene& scene, int side, double inside_m) {
  const Scenario& sc = scene.scenario;
  const ToolSpec* tool = sc.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
  const TrocarSpec* port = tool == nullptr ? nullptr : sc.trocar(tool->trocar);
  if (port == nullptr) return Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = scene.task_target_point() - port->position_m;
  axis = axis.norm() > 1e-9 ? Eigen::Vector3d(axis.normalized())
                            : Eigen::Vector3d(-Eigen::Vector3d::UnitY());
  return port->position_m - (tool->shaft_length_m - inside_m) * axis;
}

Eigen::Vector3d home_handle_position(const Scene& scene, int side) {
  constexpr double kHomeInsideM = 0.10;
  constexpr double kPastPictureEdgeM = 0.02;
  constexpr double kMaxShareOfWay = 0.6;
  constexpr double kScanStepM = 0.005;
  const Scenario& sc = scene.scenario;
  const ToolSpec* tool = sc.tool(side == 0 ? ToolSpec::Side::kLeft : ToolSpec::Side::kRight);
  const TrocarSpec* port = tool == nullptr ? nullptr : sc.trocar(tool->trocar);
  if (port == nullptr) return default_handle_position(scene, side, kHomeInsideM);
  const Eigen::Vector3d to_target = scene.task_target_point() - port->position_m;
  const double way_m = to_target.norm();
  if (!(way_m > 1e-9)) return default_handle_position(scene, side, kHomeInsideM);
  const Eigen::Vector3d axis = to_target / way_m;
  const CameraPicture picture = CameraPicture::of(sc.camera);
  const double deepest_m = std::max(kHomeInsideM, kMaxShareOfWay * way_m);
  for (double in_m = 0.0; in_m <= deepest_m; in_m += kScanStepM) {
    if (picture.contains(port->position_m + in_m * axis)) {
      const double home_m = std::clamp(in_m + kPastPictureEdgeM, kHomeInsideM, deepest_m);
      return default_handle_position(scene, side, home_m);
    }
  }
  return default_handle_position(scene, side, kHomeInsideM);  // never in view on this line
}

namespace {

Result<std::unique_ptr<hardware::HapticDevice>> make_arm(const hardware::DeviceSpec& spec,
                                                         const Scene& scene, int side) {
  const std::string name = side == 0 ? "left" : "right";
  switch (spec.kind) {
    case hardware::DeviceKind::kSimulated: {
      hardware::SimulatedInput home;
      home.position_W = home_handle_position(scene, side);
      home.gripper_angle_rad = 0.6;
      return std::unique_ptr<hardware::HapticDevice>(
          std::make_unique<hardware::SimulatedDevice>(home, name + " simulated"));
    }
    case hardware::DeviceKind::kScripted: {
      auto tr = hardware::load_scripted_trajectory(spec.argument);
      if (!tr.ok()) return tr.diagnostics();
      return std::unique_ptr<hardware::HapticDevice>(
          std::make_unique<hardware::ScriptedDevice>(std::move(tr).value(), name + " scripted"));
    }
    case hardware::DeviceKind::kReplay: {
      auto rec = hardware::read_device_recording(spec.argument);
      if (!rec.ok()) return rec.diagnostics();
      return std::unique_ptr<hardware::HapticDevice>(
          std::make_unique<hardware::ReplayDevice>(std::move(rec).value(), name + " replay"));
    }
    case hardware::DeviceKind::kPhantom: {
      // The device's origin (the middle of its workspace) at the handle's home.
      hardware::PhantomSettings ps;
      ps.device_name = spec.argument;
      ps.device_to_world =
          Eigen::Translation3d(home_handle_position(scene, side)) * Eigen::Isometry3d::Identity();
      auto dev = std::make_unique<hardware::PhantomDevice>(ps);
      // Started by the session; here only the library is checked, to fail early and clearly.
      auto api = hardware::hd::load_api(ps.library);
      if (!api.ok()) {
        return diagnostic(std::string(dev->name()) + ": " + api.message() +
                          ", or use simulated, scripted:FILE or replay:FILE.");
      }
      return std::unique_ptr<hardware::HapticDevice>(std::move(dev));
    }
  }
  return diagnostic("unknown device kind");
}

}  // namespace

Result<std::unique_ptr<hardware::HapticDevice>> make_device(const hardware::DeviceSpec& spec,
                                                            const Scene& scene, int side) {
  auto arm = make_arm(spec, scene, side);
  if (!arm.ok() || !spec.usb_gripper) return arm;
  // The actuated gripper on the arm's end (started, and checked, with the session).
  return std::unique_ptr<hardware::HapticDevice>(std::make_unique<hardware::ArmWithGripper>(
      std::move(arm).value(), std::make_unique<hardware::UsbGripper>(
                                  std::make_unique<hardware::LibusbTransport>(spec.gripper))));
}

}  // namespace lap::sim
