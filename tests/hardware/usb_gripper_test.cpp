#include "hardware/usb_gripper.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <thread>

#include "hardware/gripper_emulator.h"
#include "hardware/gripper_protocol.h"
#include "hardware/scripted_device.h"

namespace lap::hardware {
namespace {

using namespace std::chrono_literals;

TEST(GripperProtocol, CrcIsCcittFalse) {
  const char* check = "123456789";  // the CRC catalogue's check string
  EXPECT_EQ(gripper::crc16({reinterpret_cast<const uint8_t*>(check), 9}), 0x29B1);  // NOLINT
}

TEST(GripperProtocol, ReportsRoundTripAndMalformedOnesAreNamed) {
  gripper::StateReport s;
  s.flags = gripper::kFlagCalibrated;
  s.sequence = 65535;
  s.encoder_counts = -123456;
  s.motor_current_ma = -300;
  s.device_time_ms = 4242;
  auto bytes = gripper::encode(s);
  const Result<gripper::StateReport> back = gripper::decode_state(bytes);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->sequence, 65535);
  EXPECT_EQ(back->encoder_counts, -123456);
  EXPECT_EQ(back->motor_current_ma, -300);
  EXPECT_EQ(back->device_time_ms, 4242);
  // Layout: id, flags, then little-endian fields.
  EXPECT_EQ(bytes[0], 0x01);
  EXPECT_EQ(bytes[2], 0xFF);
  EXPECT_EQ(bytes[3], 0xFF);

  bytes[6] ^= 1;
  const Result<gripper::StateReport> corrupt = gripper::decode_state(bytes);
  EXPECT_FALSE(corrupt.ok());
  EXPECT_NE(corrupt.message().find("state report: CRC"), std::string::npos) << corrupt.message();
  const Result<gripper::StateReport> short_report =
      gripper::decode_state(std::span<const uint8_t>(bytes).first(9));
  EXPECT_FALSE(short_report.ok());
  EXPECT_EQ(short_report.message(), "state report: expected 16 bytes, got 9");
  gripper::CommandReport c;
  c.motor_enabled = true;
  c.sequence = 7;
  c.squeeze_mn = 1500;
  auto cb = gripper::encode(c);
  const Result<gripper::StateReport> command_as_state =
      gripper::decode_state(std::span<const uint8_t>(cb));
  EXPECT_FALSE(command_as_state.ok());
  EXPECT_EQ(command_as_state.message(), "state report: expected 16 bytes, got 8");
  const Result<gripper::CommandReport> cback = gripper::decode_command(cb);
  ASSERT_TRUE(cback.ok()) << cback.message();
  EXPECT_EQ(cback->squeeze_mn, 1500);
  EXPECT_TRUE(cback->motor_enabled);
  cb[0] = 0x07;
  const Result<gripper::CommandReport> wrong_id = gripper::decode_command(cb);
  EXPECT_FALSE(wrong_id.ok());
  EXPECT_EQ(wrong_id.message(), "command report: expected report id 0x02, got 0x07");
}

TEST(GripperProtocol, UnitConversionsClamp) {
  gripper::GripperCalibration cal;
  cal.rad_per_count = 0.001;
  cal.max_opening_rad = 1.0;
  cal.max_squeeze_n = 5.0;
  EXPECT_DOUBLE_EQ(gripper::opening_rad(cal, 500), 0.5);
  EXPECT_EQ(gripper::opening_rad(cal, -20), 0.0);
  EXPECT_EQ(gripper::opening_rad(cal, 5000), 1.0);
  EXPECT_EQ(gripper::squeeze_mn(cal, 1.2345), 1235);
  EXPECT_EQ(gripper::squeeze_mn(cal, 9.0), 5000);
  EXPECT_EQ(gripper::squeeze_mn(cal, -1.0), 0);
  EXPECT_EQ(gripper::squeeze_mn(cal, std::nan("")), 0);
}

struct Rig {
  GripperEmulator* emu = nullptr;
  std::unique_ptr<UsbGripper> gripper;
  explicit Rig(const GripperEmulator::Controls& c = {}) {
    auto e = std::make_unique<GripperEmulator>();
    e->set(c);
    emu = e.get();
    UsbGripperSettings s;
    s.calibration.rad_per_count = 0.001;
    gripper = std::make_unique<UsbGripper>(std::move(e), s);
  }
};

template <typename Pred>
bool eventually(Pred p, std::chrono::milliseconds limit = 1000ms) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (p()) return true;
    std::this_thread::sleep_for(1ms);
  }
  return p();
}

TEST(UsbGripper, ReportsTheOpeningAndSendsTheSqueezeInMillinewtons) {
  GripperEmulator::Controls c;
  c.encoder_counts = 400;
  Rig rig(c);
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  double opening = 0.0;
  EXPECT_EQ(rig.gripper->read(&opening), DeviceStatus::kOk);
  EXPECT_DOUBLE_EQ(opening, 0.4);
  c.encoder_counts = 250;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] {
    rig.gripper->read(&opening);
    return opening == 0.25;
  }));
  rig.gripper->write(2.5);
  EXPECT_TRUE(eventually([&] {
    const auto cmd = rig.emu->last_command();
    return cmd && cmd->squeeze_mn == 2500 && cmd->motor_enabled;
  }));
  rig.gripper->stop();
  const auto last = rig.emu->last_command();
  ASSERT_TRUE(last.has_value());
  EXPECT_EQ(last->squeeze_mn, 0);  // stop() turns the motor off with zero squeeze
  EXPECT_FALSE(last->motor_enabled);
}

TEST(UsbGripper, DropsAMalformedReportButAStreamOfThemIsAnError) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  GripperEmulator::Controls c = rig.emu->controls();
  c.malformed_reports = 3;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] { return rig.gripper->counters().malformed == 3; }));
  double opening = 0.0;
  EXPECT_EQ(rig.gripper->read(&opening), DeviceStatus::kOk);
  c.malformed_reports = 1000;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kError; }));
  EXPECT_NE(rig.gripper->last_error().find("malformed reports in a row (state report: CRC"),
            std::string::npos)
      << rig.gripper->last_error();
}

TEST(UsbGripper, ClearsAStalledEndpointAndGoesOn) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  GripperEmulator::Controls c = rig.emu->controls();
  c.stall_in = true;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] { return rig.gripper->counters().stalls >= 1; }));
  const int64_t before = rig.gripper->counters().reports;
  EXPECT_TRUE(eventually([&] { return rig.gripper->counters().reports > before + 5; }));
  double opening = 0.0;
  EXPECT_EQ(rig.gripper->read(&opening), DeviceStatus::kOk);
}

// Issue 25's fault injection, the other way: the OUT endpoint (squeeze commands) halts. Cleared,
// the next command gets through; one that halts again however often it is cleared is an error
// (the motor may be holding the last squeeze it got), which lasts while the commands fail and
// goes once they get through again.
TEST(UsbGripper, ClearsAStalledOutEndpointAndTheSqueezeGetsThrough) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  rig.gripper->write(1.0);
  EXPECT_TRUE(eventually([&] {
    const auto cmd = rig.emu->last_command();
    return cmd && cmd->squeeze_mn == 1000;
  }));
  GripperEmulator::Controls c = rig.emu->controls();
  c.stall_out = true;
  rig.emu->set(c);
  rig.gripper->write(2.0);
  EXPECT_TRUE(eventually([&] { return rig.gripper->counters().stalls >= 1; }));
  EXPECT_TRUE(eventually([&] {
    const auto cmd = rig.emu->last_command();
    return cmd && cmd->squeeze_mn == 2000;
  }));
  double opening = 0.0;
  EXPECT_EQ(rig.gripper->read(&opening), DeviceStatus::kOk);
  EXPECT_FALSE(rig.emu->controls().stall_out);
}

TEST(UsbGripper, AnOutEndpointThatStaysStalledIsAnErrorWhileItLasts) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  rig.gripper->write(1.5);
  EXPECT_TRUE(eventually([&] {
    const auto cmd = rig.emu->last_command();
    return cmd && cmd->squeeze_mn == 1500;
  }));
  GripperEmulator::Controls c = rig.emu->controls();
  c.stall_out = true;
  c.out_stuck = true;
  rig.emu->set(c);
  rig.gripper->write(0.0);  // the hand lets go: this zero never reaches the motor
  double opening = 0.0;
  EXPECT_TRUE(eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kError; }));
  EXPECT_NE(rig.gripper->last_error().find("20 squeeze commands in a row not sent (the OUT "
                                           "endpoint stays stalled)"),
            std::string::npos)
      << rig.gripper->last_error();
  // Reports still arrive, and do not clear the error while the commands fail.
  const int64_t reports = rig.gripper->counters().reports;
  EXPECT_TRUE(eventually([&] { return rig.gripper->counters().reports > reports + 20; }));
  EXPECT_EQ(rig.gripper->read(&opening), DeviceStatus::kError);
  EXPECT_EQ(rig.emu->last_command()->squeeze_mn, 1500);
  // The endpoint recovers: the zero gets through and the device is ok again.
  c = rig.emu->controls();
  c.out_stuck = false;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] { return rig.emu->last_command()->squeeze_mn == 0; }));
  EXPECT_TRUE(eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kOk; }));
}

TEST(UsbGripper, UnpluggedMidSessionIsLostThenReconnects) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  GripperEmulator::Controls c = rig.emu->controls();
  c.plugged = false;
  rig.emu->set(c);
  double opening = 0.0;
  EXPECT_TRUE(
      eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kDisconnected; }));
  c.plugged = true;
  c.encoder_counts = 700;
  rig.emu->set(c);
  EXPECT_TRUE(eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kOk; }));
  EXPECT_DOUBLE_EQ(opening, 0.7);
  EXPECT_GE(rig.gripper->counters().reconnects, 1);
}

TEST(UsbGripper, SilenceIsALostDevice) {
  Rig rig;
  const Status started = rig.gripper->start();
  ASSERT_TRUE(started.ok()) << started.message();
  GripperEmulator::Controls c = rig.emu->controls();
  c.timeouts = 1000;
  rig.emu->set(c);
  double opening = 0.0;
  EXPECT_TRUE(
      eventually([&] { return rig.gripper->read(&opening) == DeviceStatus::kDisconnected; }));
  EXPECT_NE(rig.gripper->last_error().find("no state report for 20 ms"), std::string::npos);
}

TEST(UsbGripper, StartRefusesAMissingOrUncalibratedGripper) {
  GripperEmulator::Controls c;
  c.plugged = false;
  Rig missing(c);
  const Status missing_started = missing.gripper->start();
  EXPECT_FALSE(missing_started.ok());
  EXPECT_EQ(missing_started.message(),
            "gripper: no actuated gripper found (USB 1209:4c54, emulated)");
  c.plugged = true;
  c.calibrated = false;
  Rig uncalibrated(c);
  const Status uncalibrated_started = uncalibrated.gripper->start();
  EXPECT_FALSE(uncalibrated_started.ok());
  EXPECT_EQ(uncalibrated_started.message(),
            "gripper: not calibrated: close the handle fully once so the jaws home");
}

TEST(ArmWithGripper, TakesThePoseFromTheArmAndTheOpeningFromTheGripper) {
  ScriptedTrajectory t;
  t.keyframes.push_back({0.0, {0.1, 0.2, 0.3}, Eigen::Quaterniond::Identity(), 0.9, 0});
  GripperEmulator::Controls c;
  c.encoder_counts = 300;
  Rig rig(c);
  GripperEmulator* emu = rig.emu;
  ArmWithGripper tool(std::make_unique<ScriptedDevice>(t, "arm"), std::move(rig.gripper));
  const Status started = tool.start();
  ASSERT_TRUE(started.ok()) << started.message();
  EXPECT_EQ(tool.name(), "arm+gripper");
  DeviceSample s;
  EXPECT_EQ(tool.read(0, 0.001, &s), DeviceStatus::kOk);
  EXPECT_EQ(s.position_W, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_DOUBLE_EQ(s.gripper_angle_rad, 0.3);
  DeviceCommand cmd;
  cmd.squeeze_n = 1.0;
  tool.write(cmd);
  EXPECT_TRUE(eventually([&] {
    const auto last = emu->last_command();
    return last && last->squeeze_mn == 1000;
  }));
  c.plugged = false;
  emu->set(c);
  EXPECT_TRUE(eventually([&] { return tool.read(1, 0.001, &s) == DeviceStatus::kDisconnected; }));
  tool.stop();
}

}  // namespace
}  // namespace lap::hardware
