#pragma once
/// \file
/// The actuated gripper, emulated behind the USB transport seam: it answers reads with state
/// reports (gripper_protocol.h) at about 1 kHz and keeps the commands it is sent, and a test
/// (or a demo) moves its jaws and makes it misbehave — malformed reports, a stalled endpoint,
/// timeouts, an unplug and replug — so every path of the driver runs without hardware.

#include <mutex>
#include <optional>

#include "hardware/gripper_protocol.h"
#include "hardware/usb_transport.h"

namespace lap::hardware {

class GripperEmulator final : public UsbTransport {
 public:
  struct Controls {
    bool plugged = true;
    bool calibrated = true;
    bool motor_fault = false;
    int32_t encoder_counts = 0;
    int malformed_reports = 0;  ///< the next n reports are corrupted
    bool stall_in = false;      ///< the IN endpoint halts until cleared
    bool stall_out = false;     ///< the OUT endpoint halts until cleared
    bool out_stuck = false;     ///< ... and clearing it does not help (it halts again at once)
    int timeouts = 0;           ///< the next n reads time out
  };

  Status open() override;
  void close() override;
  TransferResult read(std::span<uint8_t> buffer, int timeout_ms, size_t* received) override;
  TransferResult write(std::span<const uint8_t> bytes, int timeout_ms) override;
  TransferResult clear_stall(uint8_t endpoint) override;

  /// Test side (any thread).
  void set(const Controls& c);
  [[nodiscard]] Controls controls() const;
  [[nodiscard]] std::optional<gripper::CommandReport> last_command() const;

 private:
  mutable std::mutex mutex_;
  Controls controls_;
  bool open_ = false;
  uint16_t sequence_ = 0;
  std::optional<gripper::CommandReport> last_command_;
};

}  // namespace lap::hardware
