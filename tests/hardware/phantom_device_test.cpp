// The PHANToM driver against the fake libHD.so (tests/support/fake_hd.cpp).

#include "hardware/phantom_device.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/support/fake_hd_control.h"

namespace lap::hardware {
namespace {

using test::FakeHd;

void wait_ms(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }

// Polls until `done` (the fake's servo thread runs at about 1 kHz; a busy machine may delay it).
template <typename Pred>
bool eventually(Pred done) {
  for (int i = 0; i < 1000; ++i) {
    if (done()) return true;
    wait_ms(1);
  }
  return done();
}

PhantomSettings fake_settings(const std::string& name = "") {
  PhantomSettings s;
  s.library = LAP_FAKE_HD;
  s.device_name = name;
  // The device's frame 0.3 m above the world origin, turned 90° about y.
  s.device_to_world =
      Eigen::Translation3d(0, 0.3, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());
  return s;
}

class PhantomDeviceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NE(fake.handle, nullptr) << dlerror();
    fake.reset();
  }
  void TearDown() override { fake.reset(); }
  FakeHd fake;
};

TEST(PhantomDeviceNoLibrary, SaysWhatToInstall) {
  PhantomSettings s;
  s.library = "/nonexistent/libHD.so";
  PhantomDevice dev(s);
  const Status started = dev.start();
  EXPECT_FALSE(started.ok());
  const std::string error = started.message();
  EXPECT_NE(
      error.find("phantom: OpenHaptics' HD library (/nonexistent/libHD.so) could not be loaded"),
      std::string::npos)
      << error;
  EXPECT_NE(error.find("Install OpenHaptics for Linux"), std::string::npos);
  DeviceSample sample;
  EXPECT_EQ(dev.read(0, 0.001, &sample), DeviceStatus::kDisconnected);
}

TEST_F(PhantomDeviceTest, ReadsMillimetresAsMetresInTheWorldAndSendsForcesInTheDeviceFrame) {
  PhantomDevice dev(fake_settings());
  const Status started = dev.start();
  ASSERT_TRUE(started.ok()) << started.message();
  EXPECT_EQ(dev.limits().max_force_n, 3.3);
  EXPECT_EQ(dev.limits().max_continuous_force_n, 0.88);  // HD_NOMINAL_MAX_CONTINUOUS_FORCE
  EXPECT_NEAR(dev.limits().max_stiffness_n_per_m, 2310.0, 1e-9);
  EXPECT_EQ(fake.force_output_enabled(0), true);
  fake.set_state(0, {10.0, 20.0, 30.0}, {100.0, 0.0, 0.0}, 1);
  DeviceSample s;
  ASSERT_TRUE(
      eventually([&] { return dev.read(0, 0.001, &s) == DeviceStatus::kOk && s.buttons == 1; }));
  // (10, 20, 30) mm turned 90° about y is (30, 20, -10) mm, then raised 0.3 m.
  EXPECT_TRUE(s.position_W.isApprox(Eigen::Vector3d(0.030, 0.320, -0.010), 1e-12))
      << s.position_W.transpose();
  EXPECT_TRUE(s.velocity_W.isApprox(Eigen::Vector3d(0, 0, -0.1), 1e-12));
  EXPECT_EQ(s.buttons, 1U);
  // A world force along +x is along the device's +z (the turn maps device z to world x).
  DeviceCommand c;
  c.force_W = {1.0, 0.0, 0.0};
  EXPECT_EQ(dev.write(c), DeviceStatus::kOk);
  EXPECT_TRUE(eventually([&] { return fake.force(0).isApprox(Eigen::Vector3d(0, 0, 1.0), 1e-12); }))
      << fake.force(0).transpose();
  // stop() sends zero before the scheduler stops.
  dev.stop();
  EXPECT_EQ(fake.force(0), Eigen::Vector3d::Zero());
}

TEST_F(PhantomDeviceTest, TwoDevicesByName) {
  PhantomDevice left(fake_settings("Left Device"));
  PhantomDevice right(fake_settings("Right Device"));
  const Status left_started = left.start();
  ASSERT_TRUE(left_started.ok()) << left_started.message();
  const Status right_started = right.start();
  ASSERT_TRUE(right_started.ok()) << right_started.message();
  DeviceCommand a;
  a.force_W = {0, 1.0, 0};
  DeviceCommand b;
  b.force_W = {0, -2.0, 0};
  left.write(a);
  right.write(b);
  EXPECT_TRUE(eventually([&] { return fake.force(0).y() == 1.0 && fake.force(1).y() == -2.0; }))
      << fake.force(0).transpose() << " / " << fake.force(1).transpose();
  PhantomDevice missing(fake_settings("Missing Device"));
  const Status missing_started = missing.start();
  EXPECT_FALSE(missing_started.ok());
  const std::string error = missing_started.message();
  EXPECT_NE(error.find("phantom:Missing Device: hdInitDevice failed (HD error 0x0300"),
            std::string::npos)
      << error;
}

TEST_F(PhantomDeviceTest, RefusesAnUncalibratedDeviceSayingWhatToDo) {
  fake.set_calibration(0x5002);
  PhantomDevice dev(fake_settings());
  const Status started = dev.start();
  EXPECT_FALSE(started.ok());
  EXPECT_EQ(started.message(),
            "phantom: needs calibration: put the stylus in its inkwell, then start again");
}

TEST_F(PhantomDeviceTest, AServoErrorIsAnErrorAndAnUnpluggedDeviceIsLost) {
  PhantomDevice dev(fake_settings());
  const Status started = dev.start();
  ASSERT_TRUE(started.ok()) << started.message();
  wait_ms(10);
  DeviceSample s;
  EXPECT_EQ(dev.read(0, 0.001, &s), DeviceStatus::kOk);
  fake.unplug(0, true);
  wait_ms(10);
  DeviceStatus st = DeviceStatus::kOk;
  for (int i = 0; i < 40 && st == DeviceStatus::kOk; ++i) {
    st = dev.read(i, 0.001, &s);
    wait_ms(1);
  }
  EXPECT_EQ(st, DeviceStatus::kDisconnected);
  fake.unplug(0, false);
  fake.set_servo_error(0x0204);  // a force error
  EXPECT_TRUE(eventually([&] { return dev.read(0, 0.001, &s) == DeviceStatus::kError; }));
  EXPECT_EQ(dev.last_error(), "HD error 0x0204 in the servo loop");
}

}  // namespace
}  // namespace lap::hardware
