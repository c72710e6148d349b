#include "hardware/gripper_emulator.h"

#include <chrono>
#include <cstring>
#include <thread>

namespace lap::hardware {

Status GripperEmulator::open() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!controls_.plugged) return diagnostic("no actuated gripper found (USB 1209:4c54, emulated)");
  open_ = true;
  return {};
}

void GripperEmulator::close() {
  const std::lock_guard<std::mutex> lock(mutex_);
  open_ = false;
}

TransferResult GripperEmulator::read(std::span<uint8_t> buffer, int timeout_ms, size_t* received) {
  *received = 0;
  std::array<uint8_t, gripper::kStateReportBytes> report{};
  size_t size = report.size();
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!controls_.plugged || !open_) return TransferResult::kNoDevice;
    if (controls_.stall_in) return TransferResult::kStall;
    if (controls_.timeouts > 0) {
      --controls_.timeouts;
    } else {
      gripper::StateReport s;
      s.flags = static_cast<uint8_t>((controls_.calibrated ? gripper::kFlagCalibrated : 0) |
                                     (controls_.motor_fault ? gripper::kFlagMotorFault : 0));
      s.sequence = ++sequence_;
      s.encoder_counts = controls_.encoder_counts;
      report = gripper::encode(s);
      if (controls_.malformed_reports > 0) {
        --controls_.malformed_reports;
        report[5] ^= 0x40;  // a flipped bit: the CRC no longer matches
      }
      size = report.size();
      timeout_ms = 1;  // the device reports every millisecond
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
  if (timeout_ms != 1) return TransferResult::kTimeout;
  const size_t n = std::min(size, buffer.size());
  std::memcpy(buffer.data(), report.data(), n);
  *received = n;
  return TransferResult::kOk;
}

TransferResult GripperEmulator::write(std::span<const uint8_t> bytes, int /*timeout_ms*/) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!controls_.plugged || !open_) return TransferResult::kNoDevice;
  if (controls_.stall_out) return TransferResult::kStall;  // nothing reaches the motor
  if (const Result<gripper::CommandReport> c = gripper::decode_command(bytes); c.ok()) {
    last_command_ = c.value();
  }
  return TransferResult::kOk;
}

TransferResult GripperEmulator::clear_stall(uint8_t endpoint) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!controls_.plugged || !open_) return TransferResult::kNoDevice;
  if (endpoint == gripper::kEndpointIn) controls_.stall_in = false;
  if (endpoint == gripper::kEndpointOut && !controls_.out_stuck) controls_.stall_out = false;
  return TransferResult::kOk;
}

void GripperEmulator::set(const Controls& c) {
  const std::lock_guard<std::mutex> lock(mutex_);
  controls_ = c;
  if (!c.plugged) open_ = false;
}

GripperEmulator::Controls GripperEmulator::controls() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return controls_;
}

std::optional<gripper::CommandReport> GripperEmulator::last_command() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return last_command_;
}

}  // namespace lap::hardware
