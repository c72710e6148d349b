#pragma once
/// \file
/// The actuated laparoscopic gripper's driver (thesis §7.5): a USB I/O thread reads the state
/// reports (jaw opening from the encoder) and sends the newest squeeze command to the motor, and
/// trades both with the haptic loop through triple buffers. Over any UsbTransport: libusb for
/// the device, the emulator for tests.
///
/// - A malformed report is dropped and counted; more than `max_bad_reports` in a row is an error.
/// - A stalled endpoint is cleared and the transfer retried. Squeeze commands that cannot be sent
///   `max_failed_writes` times in a row (an OUT endpoint that halts again however often it is
///   cleared) are an error, which stays while they fail: the motor may be holding the last
///   squeeze it got, so the session must pause (its watchdog) rather than go on feeling nothing.
/// - No report for `stale_after_ms` is a lost device; so is an unplug. The I/O thread then
///   tries to reopen it every `reconnect_interval_ms` (hot-plug by polling, which works on every
///   libusb back end) and reports kOk again once a valid report arrives.
/// - Not calibrated (no homing since power-up), a motor fault or over-temperature: kError.

#include <atomic>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>

#include "hardware/gripper_protocol.h"
#include "hardware/haptic_device.h"
#include "hardware/triple_buffer.h"
#include "hardware/usb_transport.h"

namespace lap::hardware {

struct UsbGripperSettings {
  gripper::GripperCalibration calibration;
  int read_timeout_ms = 5;
  int write_timeout_ms = 5;
  int stale_after_ms = 20;
  int reconnect_interval_ms = 100;
  int max_bad_reports = 10;
  int max_failed_writes = 20;  ///< about 20 ms of commands at the reports' 1 kHz
  int start_timeout_ms = 200;  ///< start() waits this long for the first valid report
};

struct UsbGripperCounters {
  int64_t reports = 0;
  int64_t malformed = 0;
  int64_t stalls = 0;
  int64_t timeouts = 0;
  int64_t reconnects = 0;
};

class UsbGripper {
 public:
  UsbGripper(std::unique_ptr<UsbTransport> transport, const UsbGripperSettings& settings = {});
  ~UsbGripper();
  UsbGripper(const UsbGripper&) = delete;
  UsbGripper& operator=(const UsbGripper&) = delete;
  UsbGripper(UsbGripper&&) = delete;
  UsbGripper& operator=(UsbGripper&&) = delete;

  /// Opens the device and waits for its first valid report; a diagnostic otherwise.
  Status start();
  /// Zero squeeze, motor off, then close.
  void stop();

  /// Haptic thread: the newest opening [rad] and the device's state.
  DeviceStatus read(double* opening_rad) noexcept;
  /// Haptic thread: the squeeze to render [N] (clamped to the calibration's limit).
  void write(double squeeze_n) noexcept;

  [[nodiscard]] UsbGripperCounters counters() const;
  [[nodiscard]] std::string last_error() const;
  [[nodiscard]] const UsbGripperSettings& settings() const { return settings_; }

 private:
  void io_loop();
  /// The I/O thread's stages: a state report taken in (true when it was well formed), the
  /// squeeze command sent (false when the device is gone).
  bool take_report(std::span<const uint8_t> bytes, int* bad_run);
  bool send_squeeze(uint16_t* sequence);
  int failed_writes_ = 0;  ///< in a row; the I/O thread's own
  void set_error(DeviceStatus status, const std::string& why);

  std::unique_ptr<UsbTransport> transport_;
  UsbGripperSettings settings_;
  std::thread io_;
  std::atomic<bool> running_{false};
  std::atomic<uint8_t> status_{static_cast<uint8_t>(DeviceStatus::kDisconnected)};
  TripleBuffer<double> opening_;  // I/O → haptic
  TripleBuffer<double> squeeze_;  // haptic → I/O [N]
  std::atomic<int64_t> reports_{0}, malformed_{0}, stalls_{0}, timeouts_{0}, reconnects_{0};
  mutable std::mutex error_mutex_;  // the I/O thread and the UI only
  std::string last_error_;
};

/// A tool's device: an arm (PHANToM, scripted, ...) with the actuated gripper on its end
/// (Figure 7-9): position and orientation from the arm, the opening from the gripper; force to
/// the arm, squeeze to the gripper. Its status is the worse of the two.
class ArmWithGripper final : public HapticDevice {
 public:
  ArmWithGripper(std::unique_ptr<HapticDevice> arm, std::unique_ptr<UsbGripper> gripper);
  Status start() override;
  void stop() override;
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  DeviceStatus write(const DeviceCommand& command) noexcept override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return name_; }
  [[nodiscard]] std::string last_error() const override;

 private:
  std::unique_ptr<HapticDevice> arm_;
  std::unique_ptr<UsbGripper> gripper_;
  DeviceLimits limits_;
  std::string name_;
};

}  // namespace lap::hardware
