#include "hardware/gripper_protocol.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lap::hardware::gripper {
namespace {

void put16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void put32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}
uint16_t get16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t get32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

Status check(std::span<const uint8_t> b, size_t size, uint8_t id, const char* what) {
  auto fail = [&](const std::string& why) -> Status {
    return diagnostic(std::string(what) + ": " + why);
  };
  if (b.size() != size) {
    return fail("expected " + std::to_string(size) + " bytes, got " + std::to_string(b.size()));
  }
  if (b[0] != id) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "expected report id 0x%02x, got 0x%02x", id, b[0]);
    return fail(buf);
  }
  const uint16_t want = crc16(b.first(size - 2));
  const uint16_t got = get16(&b[size - 2]);
  if (want != got) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "CRC 0x%04x does not match the contents (0x%04x)", got, want);
    return fail(buf);
  }
  return {};
}

}  // namespace

uint16_t crc16(std::span<const uint8_t> bytes) {
  uint16_t crc = 0xFFFF;
  for (const uint8_t byte : bytes) {
    crc ^= static_cast<uint16_t>(byte << 8);
    for (int i = 0; i < 8; ++i) {
      crc = (crc & 0x8000) != 0 ? static_cast<uint16_t>((crc << 1) ^ 0x1021)
                                : static_cast<uint16_t>(crc << 1);
    }
  }
  return crc;
}

std::array<uint8_t, kStateReportBytes> encode(const StateReport& r) {
  std::array<uint8_t, kStateReportBytes> b{};
  b[0] = kStateReportId;
  b[1] = r.flags;
  put16(&b[2], r.sequence);
  put32(&b[4], static_cast<uint32_t>(r.encoder_counts));
  put16(&b[8], static_cast<uint16_t>(r.motor_current_ma));
  put16(&b[10], r.device_time_ms);
  put16(&b[14], crc16(std::span<const uint8_t>(b).first(14)));
  return b;
}

std::array<uint8_t, kCommandReportBytes> encode(const CommandReport& r) {
  std::array<uint8_t, kCommandReportBytes> b{};
  b[0] = kCommandReportId;
  b[1] = r.motor_enabled ? 1 : 0;
  put16(&b[2], r.sequence);
  put16(&b[4], static_cast<uint16_t>(r.squeeze_mn));
  put16(&b[6], crc16(std::span<const uint8_t>(b).first(6)));
  return b;
}

Result<StateReport> decode_state(std::span<const uint8_t> b) {
  if (Status s = check(b, kStateReportBytes, kStateReportId, "state report"); !s.ok()) {
    return s.diagnostics();
  }
  StateReport r;
  r.flags = b[1];
  r.sequence = get16(&b[2]);
  r.encoder_counts = static_cast<int32_t>(get32(&b[4]));
  r.motor_current_ma = static_cast<int16_t>(get16(&b[8]));
  r.device_time_ms = get16(&b[10]);
  return r;
}

Result<CommandReport> decode_command(std::span<const uint8_t> b) {
  if (Status s = check(b, kCommandReportBytes, kCommandReportId, "command report"); !s.ok()) {
    return s.diagnostics();
  }
  CommandReport r;
  r.motor_enabled = (b[1] & 1) != 0;
  r.sequence = get16(&b[2]);
  r.squeeze_mn = static_cast<int16_t>(get16(&b[4]));
  return r;
}

double opening_rad(const GripperCalibration& c, int32_t counts) {
  return std::clamp(static_cast<double>(counts) * c.rad_per_count, 0.0, c.max_opening_rad);
}

int16_t squeeze_mn(const GripperCalibration& c, double squeeze_n) {
  if (!std::isfinite(squeeze_n)) return 0;
  const double mn = std::clamp(squeeze_n, 0.0, std::min(c.max_squeeze_n, 32.767)) * 1000.0;
  return static_cast<int16_t>(std::lround(mn));
}

}  // namespace lap::hardware::gripper
