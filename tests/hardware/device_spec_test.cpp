#include "hardware/device_spec.h"

#include <gtest/gtest.h>

namespace lap::hardware {
namespace {

TEST(DeviceSpec, ParsesEveryForm) {
  EXPECT_EQ(parse_device_spec("simulated")->kind, DeviceKind::kSimulated);
  const Result<DeviceSpec> s = parse_device_spec("scripted:paths/left.csv");
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->kind, DeviceKind::kScripted);
  EXPECT_EQ(s->argument, "paths/left.csv");
  EXPECT_EQ(parse_device_spec("replay:run1")->kind, DeviceKind::kReplay);
  EXPECT_EQ(parse_device_spec("phantom")->argument, "");
  EXPECT_EQ(parse_device_spec("phantom:Left Device")->argument, "Left Device");
  EXPECT_FALSE(parse_device_spec("phantom:Left Device")->usb_gripper);
  const Result<DeviceSpec> g = parse_device_spec("phantom:Left Device+gripper");
  ASSERT_TRUE(g.ok()) << g.message();
  EXPECT_EQ(g->argument, "Left Device");
  EXPECT_TRUE(g->usb_gripper);
  EXPECT_TRUE(parse_device_spec("scripted:a.csv+gripper")->usb_gripper);
  EXPECT_EQ(parse_device_spec("scripted:a.csv+gripper")->argument, "a.csv");
}

TEST(DeviceSpec, RejectsWithAClearMessage) {
  const Result<DeviceSpec> scripted = parse_device_spec("scripted");
  EXPECT_FALSE(scripted.ok());
  EXPECT_EQ(scripted.message(), "device 'scripted': expected scripted:FILE");
  const Result<DeviceSpec> mouse = parse_device_spec("mouse");
  EXPECT_FALSE(mouse.ok());
  EXPECT_EQ(
      mouse.message(),
      "device 'mouse': expected simulated, scripted:FILE, replay:FILE, phantom or phantom:NAME "
      "(each optionally +gripper)");
  const Result<DeviceSpec> simulated = parse_device_spec("simulated:x");
  EXPECT_FALSE(simulated.ok());
  EXPECT_EQ(simulated.message(), "device 'simulated:x': 'simulated' takes no argument");
}

}  // namespace
}  // namespace lap::hardware
