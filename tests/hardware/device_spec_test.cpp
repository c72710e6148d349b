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

// Two grippers, two tools: each DEV names its own by serial or by where it is plugged.
TEST(DeviceSpec, NamesWhichGripperBySerialOrBusPath) {
  const Result<DeviceSpec> serial = parse_device_spec("phantom:Left+gripper:LT-0042");
  ASSERT_TRUE(serial.ok()) << serial.message();
  EXPECT_EQ(serial->argument, "Left");
  EXPECT_TRUE(serial->usb_gripper);
  EXPECT_EQ(serial->gripper.serial, "LT-0042");
  EXPECT_TRUE(serial->gripper.bus_path.empty());
  const Result<DeviceSpec> path = parse_device_spec("simulated+gripper@1-2.3");
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_EQ(path->kind, DeviceKind::kSimulated);
  EXPECT_EQ(path->gripper.bus_path, "1-2.3");
  EXPECT_TRUE(parse_device_spec("phantom+gripper")->gripper.serial.empty());
  // A file name holding "+gripper" is a file name; a malformed selector is refused.
  const Result<DeviceSpec> file = parse_device_spec("scripted:/tmp/a+gripper.csv");
  ASSERT_TRUE(file.ok()) << file.message();
  EXPECT_EQ(file->argument, "/tmp/a+gripper.csv");
  EXPECT_FALSE(file->usb_gripper);
  for (const char* bad : {"phantom+gripper@x-1", "phantom+gripper@12", "phantom+gripper@1-",
                          "phantom+gripper@1-2..3", "phantom+gripper@-2"}) {
    const Result<DeviceSpec> r = parse_device_spec(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.message().find("expected +gripper@BUS-PORTS"), std::string::npos) << r.message();
  }
  EXPECT_FALSE(parse_device_spec("phantom+gripper:").ok());  // 'phantom+gripper:' is no arm
}

TEST(GripperSelection, TheOnlyOneOrTheNamedOne) {
  const std::vector<FoundGripper> two = {{"LT-0042", "1-2"}, {"", "1-3.1"}};
  EXPECT_EQ(select_gripper({{"A", "1-4"}}, {}).value(), 0U);
  EXPECT_EQ(select_gripper(two, {"LT-0042", ""}).value(), 0U);
  EXPECT_EQ(select_gripper(two, {"", "1-3.1"}).value(), 1U);
  const Result<size_t> ambiguous = select_gripper(two, {});
  ASSERT_FALSE(ambiguous.ok());
  EXPECT_EQ(ambiguous.message(),
            "2 actuated grippers found (serial LT-0042 at 1-2, serial (unreadable) at 1-3.1): name "
            "the tool's with +gripper:SERIAL or +gripper@BUS-PORTS");
  EXPECT_EQ(select_gripper(two, {"LT-9", ""}).message(),
            "no actuated gripper with serial 'LT-9' (found: serial LT-0042 at 1-2, serial "
            "(unreadable) at 1-3.1)");
  EXPECT_EQ(select_gripper(two, {"", "2-1"}).message(),
            "no actuated gripper plugged in at 2-1 (found: serial LT-0042 at 1-2, serial "
            "(unreadable) at 1-3.1)");
  EXPECT_NE(select_gripper({}, {}).message().find("no actuated gripper found (USB 1209:4c54)"),
            std::string::npos);
}

}  // namespace
}  // namespace lap::hardware
