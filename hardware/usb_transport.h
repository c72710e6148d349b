#pragma once
/// \file
/// The seam between the gripper driver and USB: open, interrupt IN/OUT transfers with timeouts,
/// close. libusb behind it for the real device (libusb_transport.h), an emulator of the gripper
/// for tests (gripper_emulator.h), so every path — normal, malformed report, stalled endpoint,
/// unplugged — runs without hardware.

#include <cstdint>
#include <span>
#include <string>

#include "core/result.h"

namespace lap::hardware {

enum class TransferResult : uint8_t {
  kOk,
  kTimeout,   ///< nothing within the timeout
  kStall,     ///< the endpoint halted (the driver clears it and goes on)
  kNoDevice,  ///< unplugged
  kError,     ///< anything else
};

class UsbTransport {
 public:
  UsbTransport() = default;
  UsbTransport(const UsbTransport&) = delete;
  UsbTransport& operator=(const UsbTransport&) = delete;
  UsbTransport(UsbTransport&&) = delete;
  UsbTransport& operator=(UsbTransport&&) = delete;
  virtual ~UsbTransport() = default;

  /// Finds and claims the device; a diagnostic when it is not there.
  virtual Status open() = 0;
  virtual void close() = 0;
  /// One interrupt IN transfer into `buffer`; *received bytes arrived.
  virtual TransferResult read(std::span<uint8_t> buffer, int timeout_ms, size_t* received) = 0;
  /// One interrupt OUT transfer.
  virtual TransferResult write(std::span<const uint8_t> bytes, int timeout_ms) = 0;
  /// Clears a halted endpoint (after kStall).
  virtual TransferResult clear_stall(uint8_t endpoint) = 0;
};

}  // namespace lap::hardware
