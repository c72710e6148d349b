#include "hardware/phantom_device.h"

#include <chrono>
#include <cstdio>
#include <thread>
#include <utility>

namespace lap::hardware {
namespace {

// HD_NOMINAL_MAX_CONTINUOUS_FORCE [N]: 0x2604 in OpenHaptics' hdDefines.h, next to
// HD_NOMINAL_MAX_FORCE (0x2603, hd::kNominalMaxForce).
constexpr hd::HDenum kNominalMaxContinuousForce = 0x2604;

std::string hex(unsigned int code) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%04x", code);
  return buf;
}

}  // namespace

PhantomDevice::PhantomDevice(PhantomSettings settings)
    : settings_(std::move(settings)),
      label_("phantom" + (settings_.device_name.empty() ? "" : ":" + settings_.device_name)),
      forces_(Eigen::Vector3d::Zero()) {}

PhantomDevice::~PhantomDevice() { stop(); }

Status PhantomDevice::start() {
  auto fail = [&](const std::string& why) -> Status { return diagnostic(label_ + ": " + why); };
  Result<std::shared_ptr<hd::Api>> loaded = hd::load_api(settings_.library);
  if (!loaded.ok()) {
    api_.reset();
    return fail(loaded.message());
  }
  api_ = std::move(loaded).value();
  const hd::Api& a = *api_;
  (void)a.hdGetError();  // clear anything pending
  hhd_ = a.hdInitDevice(settings_.device_name.empty() ? nullptr : settings_.device_name.c_str());
  hd::HDErrorInfo e = a.hdGetError();
  if (hhd_ == hd::kInvalidHandle || e.errorCode != hd::kSuccess) {
    hhd_ = hd::kInvalidHandle;
    return fail("hdInitDevice failed (HD error " + hex(e.errorCode) + ", internal " +
                std::to_string(e.internalErrorCode) +
                "): is the device plugged in, powered and named so in Touch Setup?");
  }
  a.hdMakeCurrentDevice(hhd_);
  const hd::HDenum calibration = a.hdCheckCalibration();
  if (calibration != hd::kCalibrationOk) {
    a.hdDisableDevice(hhd_);
    hhd_ = hd::kInvalidHandle;
    return fail(calibration == hd::kCalibrationNeedsManualInput
                    ? "needs calibration: put the stylus in its inkwell, then start again"
                    : "needs calibration: run Touch Diagnostic's calibration, then start again");
  }
  double max_force = 0.0;
  double max_continuous_force = 0.0;
  double max_stiffness_n_per_mm = 0.0;
  a.hdGetDoublev(hd::kNominalMaxForce, &max_force);
  a.hdGetDoublev(kNominalMaxContinuousForce, &max_continuous_force);
  a.hdGetDoublev(hd::kNominalMaxStiffness, &max_stiffness_n_per_mm);
  if (max_force > 0.0) limits_.max_force_n = max_force;
  // The force the motors sustain without overheating (SensAble's own examples ramp their force
  // clamp down to it when the motors warm); CommandLimiter bounds the sustained output by it.
  if (max_continuous_force > 0.0) limits_.max_continuous_force_n = max_continuous_force;
  if (max_stiffness_n_per_mm > 0.0) limits_.max_stiffness_n_per_m = 1000.0 * max_stiffness_n_per_mm;
  limits_.max_torque_nm = 0.0;  // a 3-DOF arm
  a.hdEnable(hd::kForceOutput);
  a.hdEnable(hd::kForceRamping);
  zero_force_.store(true);
  callback_ = a.hdScheduleAsynchronous(&PhantomDevice::servo, this, hd::kMaxSchedulerPriority);
  // One scheduler serves every device: (re)start it so it picks this one up.
  if (api_->scheduler_users > 0) a.hdStopScheduler();
  a.hdStartScheduler();
  ++api_->scheduler_users;
  e = a.hdGetError();
  if (e.errorCode != hd::kSuccess) {
    running_ = true;
    stop();
    return fail("the HD scheduler did not start (HD error " + hex(e.errorCode) + ")");
  }
  running_ = true;
  zero_force_.store(false);
  last_count_ = 0;
  stale_ = 0;
  return {};
}

void PhantomDevice::stop() {
  if (!running_) return;
  running_ = false;
  // Zero force first, and let the servo send it.
  zero_force_.store(true);
  const uint64_t frames = servo_frames_.load();
  for (int i = 0; i < 50 && servo_frames_.load() < frames + 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const hd::Api& a = *api_;
  a.hdStopScheduler();
  a.hdUnschedule(callback_);
  a.hdDisableDevice(hhd_);
  hhd_ = hd::kInvalidHandle;
  if (--api_->scheduler_users > 0) a.hdStartScheduler();
}

hd::HDCallbackCode PhantomDevice::servo(void* self_ptr) {
  auto* self = static_cast<PhantomDevice*>(self_ptr);
  const hd::Api& a = *self->api_;
  a.hdBeginFrame(self->hhd_);
  ServoSample& s = self->samples_.write_slot();
  a.hdGetDoublev(hd::kCurrentPosition, s.position_mm);
  a.hdGetDoublev(hd::kCurrentVelocity, s.velocity_mm_s);
  a.hdGetDoublev(hd::kCurrentTransform, s.transform);
  a.hdGetIntegerv(hd::kCurrentButtons, &s.buttons);
  // After a servo error the arm gets zero force from here on, without waiting for the haptic
  // loop to notice (it will, and pause the session).
  const bool zero = self->zero_force_.load(std::memory_order_relaxed) ||
                    self->servo_error_.load(std::memory_order_relaxed) != 0;
  const Eigen::Vector3d f = zero ? Eigen::Vector3d::Zero() : self->forces_.latest();
  a.hdSetDoublev(hd::kCurrentForce, f.data());
  a.hdEndFrame(self->hhd_);
  const hd::HDErrorInfo e = a.hdGetError();
  if (e.errorCode != hd::kSuccess) self->servo_error_.store(e.errorCode, std::memory_order_relaxed);
  s.count = self->servo_frames_.fetch_add(1, std::memory_order_relaxed) + 1;
  self->samples_.publish();
  return hd::kCallbackContinue;
}

DeviceStatus PhantomDevice::read(int64_t /*tick*/, double /*period_s*/,
                                 DeviceSample* out) noexcept {
  if (!running_) return DeviceStatus::kDisconnected;
  const ServoSample& s = samples_.latest();
  const Eigen::Isometry3d& X = settings_.device_to_world;
  const Eigen::Map<const Eigen::Matrix4d> T(s.transform);
  out->position_W =
      X * (1e-3 * Eigen::Vector3d(s.position_mm[0], s.position_mm[1], s.position_mm[2]));
  out->velocity_W = X.linear() * (1e-3 * Eigen::Vector3d(s.velocity_mm_s[0], s.velocity_mm_s[1],
                                                         s.velocity_mm_s[2]));
  out->orientation_W = Eigen::Quaterniond(X.linear() * T.topLeftCorner<3, 3>());
  out->buttons = static_cast<uint32_t>(s.buttons);
  out->time_s = static_cast<double>(s.count) * 1e-3;
  if (servo_error_.load(std::memory_order_relaxed) != 0) return DeviceStatus::kError;
  if (s.count == last_count_) {
    if (++stale_ > settings_.stale_reads) return DeviceStatus::kDisconnected;
  } else {
    stale_ = 0;
    last_count_ = s.count;
  }
  return DeviceStatus::kOk;
}

DeviceStatus PhantomDevice::write(const DeviceCommand& command) noexcept {
  forces_.publish(settings_.device_to_world.linear().transpose() * command.force_W);
  return servo_error_.load(std::memory_order_relaxed) != 0 ? DeviceStatus::kError
                                                           : DeviceStatus::kOk;
}

std::string PhantomDevice::last_error() const {
  const unsigned int e = servo_error_.load();
  return e == 0 ? std::string() : "HD error " + hex(e) + " in the servo loop";
}

}  // namespace lap::hardware
