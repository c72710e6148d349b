#pragma once
/// \file
/// The USB protocol of laptrainer's actuated laparoscopic gripper (thesis §7.5, Figure 7-8: an
/// encoder and a motor on the instrument's handle). Documented in hardware/README.md; this file
/// is its one implementation: report layouts, the CRC, and the conversions to SI units.
///
/// All multi-byte fields are little-endian. Both reports end in a CRC-16/CCITT-FALSE (poly
/// 0x1021, init 0xFFFF, no reflection, no final xor) over every byte before it.

#include <array>
#include <cstdint>
#include <span>

#include "core/result.h"

namespace lap::hardware::gripper {

inline constexpr uint16_t kVendorId = 0x1209;   ///< pid.codes (open hardware)
inline constexpr uint16_t kProductId = 0x4C54;  ///< "LT"; to be registered with pid.codes
inline constexpr uint8_t kInterface = 0;
inline constexpr uint8_t kEndpointIn = 0x81;   ///< interrupt IN, state reports
inline constexpr uint8_t kEndpointOut = 0x01;  ///< interrupt OUT, commands
inline constexpr size_t kStateReportBytes = 16;
inline constexpr size_t kCommandReportBytes = 8;
inline constexpr uint8_t kStateReportId = 0x01;
inline constexpr uint8_t kCommandReportId = 0x02;

/// State flags (byte 1 of the state report).
inline constexpr uint8_t kFlagCalibrated = 0x01;  ///< homed against the closed stop since power-up
inline constexpr uint8_t kFlagMotorFault = 0x02;
inline constexpr uint8_t kFlagOverTemperature = 0x04;

/// Device → host, every 1 ms.
struct StateReport {
  uint8_t flags = 0;
  uint16_t sequence = 0;
  int32_t encoder_counts = 0;  ///< jaw opening, 0 at the closed stop
  int16_t motor_current_ma = 0;
  uint16_t device_time_ms = 0;  ///< wraps
};

/// Host → device.
struct CommandReport {
  bool motor_enabled = false;
  uint16_t sequence = 0;
  int16_t squeeze_mn = 0;  ///< force resisting closure [mN]; ≥ 0
};

/// Calibration of one instrument (hardware/README.md): counts to radians of opening.
struct GripperCalibration {
  double rad_per_count = 1.0 / 4096.0 * 0.5;  ///< 4096-count encoder, 2:1 to the jaws
  double max_opening_rad = 1.0;               ///< the mechanical open stop
  double max_squeeze_n = 5.0;                 ///< the motor's continuous limit at the jaws
};

[[nodiscard]] uint16_t crc16(std::span<const uint8_t> bytes);

[[nodiscard]] std::array<uint8_t, kStateReportBytes> encode(const StateReport& r);
[[nodiscard]] std::array<uint8_t, kCommandReportBytes> encode(const CommandReport& r);

// Decoding runs on the gripper's USB I/O thread (UsbGripper::io_loop) and in the emulator, never
// on the haptic thread (UsbGripper::read only takes a triple buffer). A valid report allocates
// nothing (an ok Result holds no diagnostics); a malformed one builds its message.

/// Parses a state report; a diagnostic saying what was wrong for a malformed one.
[[nodiscard]] Result<StateReport> decode_state(std::span<const uint8_t> bytes);
/// Parses a command report; a diagnostic saying what was wrong for a malformed one.
[[nodiscard]] Result<CommandReport> decode_command(std::span<const uint8_t> bytes);

/// Opening angle [rad] from counts, clamped to [0, max_opening_rad].
[[nodiscard]] double opening_rad(const GripperCalibration& c, int32_t counts);
/// Squeeze command [mN] from newtons, clamped to [0, max_squeeze_n] (NaN → 0).
[[nodiscard]] int16_t squeeze_mn(const GripperCalibration& c, double squeeze_n);

}  // namespace lap::hardware::gripper
