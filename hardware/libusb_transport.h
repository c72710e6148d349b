#pragma once
/// \file
/// UsbTransport over libusb-1.0 for the actuated gripper (gripper_protocol.h's ids and
/// endpoints). The only file in the project that includes libusb (docs/architecture.md).

#include <memory>
#include <vector>

#include "hardware/gripper_selection.h"
#include "hardware/usb_transport.h"

namespace lap::hardware {

class LibusbTransport final : public UsbTransport {
 public:
  /// Opens the gripper `selector` names (gripper_selection.h), or the only one plugged in.
  explicit LibusbTransport(GripperSelector selector = {});
  ~LibusbTransport() override;
  LibusbTransport(const LibusbTransport&) = delete;
  LibusbTransport& operator=(const LibusbTransport&) = delete;
  LibusbTransport(LibusbTransport&&) = delete;
  LibusbTransport& operator=(LibusbTransport&&) = delete;

  Status open() override;
  void close() override;
  TransferResult read(std::span<uint8_t> buffer, int timeout_ms, size_t* received) override;
  TransferResult write(std::span<const uint8_t> bytes, int timeout_ms) override;
  TransferResult clear_stall(uint8_t endpoint) override;

  /// The grippers plugged in now (serials need permission to open them: empty where refused).
  [[nodiscard]] static Result<std::vector<FoundGripper>> list();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lap::hardware
