#include "hardware/device_spec.h"

#include <gtest/gtest.h>

namespace lap::hardware {
namespace {

TEST(DeviceSpec, ParsesEveryForm) {
  std::string error;
  EXPECT_EQ(parse_device_spec("simulated", &error)->kind, DeviceKind::kSimulated);
  const auto s = parse_device_spec("scripted:paths/left.csv", &error);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->kind, DeviceKind::kScripted);
  EXPECT_EQ(s->argument, "paths/left.csv");
  EXPECT_EQ(parse_device_spec("replay:run1", &error)->kind, DeviceKind::kReplay);
  EXPECT_EQ(parse_device_spec("phantom", &error)->argument, "");
  EXPECT_EQ(parse_device_spec("phantom:Left Device", &error)->argument, "Left Device");
  EXPECT_FALSE(parse_device_spec("phantom:Left Device", &error)->usb_gripper);
  const auto g = parse_device_spec("phantom:Left Device+gripper", &error);
  ASSERT_TRUE(g);
  EXPECT_EQ(g->argument, "Left Device");
  EXPECT_TRUE(g->usb_gripper);
  EXPECT_TRUE(parse_device_spec("scripted:a.csv+gripper", &error)->usb_gripper);
  EXPECT_EQ(parse_device_spec("scripted:a.csv+gripper", &error)->argument, "a.csv");
}

TEST(DeviceSpec, RejectsWithAClearMessage) {
  std::string error;
  EXPECT_FALSE(parse_device_spec("scripted", &error));
  EXPECT_EQ(error, "device 'scripted': expected scripted:FILE");
  EXPECT_FALSE(parse_device_spec("mouse", &error));
  EXPECT_EQ(
      error,
      "device 'mouse': expected simulated, scripted:FILE, replay:FILE, phantom or phantom:NAME "
      "(each optionally +gripper)");
  EXPECT_FALSE(parse_device_spec("simulated:x", &error));
}

}  // namespace
}  // namespace lap::hardware
