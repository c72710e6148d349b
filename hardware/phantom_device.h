#pragma once
/// \file
/// A PHANToM / Touch arm through OpenHaptics' HD API (thesis §7.5: two PHANToMs, one per tool).
/// libHD.so is loaded at run time (open_haptics_api.h). The HD scheduler's servo callback
/// (hdScheduleAsynchronous, hdBeginFrame ... hdEndFrame) reads position, velocity, transform and
/// buttons and writes the newest force; it trades samples and commands with the haptic loop
/// through triple buffers, so neither thread waits for the other.
///
/// - Units: the HD API reports millimetres; samples leave here in metres, in the world frame
///   (`device_to_world` places the device's frame).
/// - Safety: force output starts with OpenHaptics' force ramping enabled; stop() zeroes the force
///   before the scheduler stops; after a servo error the servo itself sends zero force and the
///   error is reported as kError; a servo that stops
///   delivering samples (unplugged) as kDisconnected after `stale_reads` reads.
/// - Calibration is checked at start: a device that needs it is refused with what to do.
/// - Two devices by name (`phantom:NAME`, the names of the Touch Setup configuration).

#include <atomic>
#include <memory>
#include <string>

#include "hardware/haptic_device.h"
#include "hardware/open_haptics_api.h"
#include "hardware/triple_buffer.h"

namespace lap::hardware {

struct PhantomSettings {
  std::string device_name;  ///< empty: the default device
  std::string library = "libHD.so";
  Eigen::Isometry3d device_to_world = Eigen::Isometry3d::Identity();  ///< device frame [m] → W
  int stale_reads = 20;  ///< reads without a new servo sample before the device counts as lost
};

class PhantomDevice final : public HapticDevice {
 public:
  explicit PhantomDevice(PhantomSettings settings);
  ~PhantomDevice() override;
  PhantomDevice(const PhantomDevice&) = delete;
  PhantomDevice& operator=(const PhantomDevice&) = delete;
  PhantomDevice(PhantomDevice&&) = delete;
  PhantomDevice& operator=(PhantomDevice&&) = delete;

  Status start() override;
  void stop() override;
  DeviceStatus read(int64_t tick, double period_s, DeviceSample* out) noexcept override;
  DeviceStatus write(const DeviceCommand& command) noexcept override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] std::string_view name() const override { return label_; }
  [[nodiscard]] std::string last_error() const override;

 private:
  struct ServoSample {
    uint64_t count = 0;
    double position_mm[3] = {0, 0, 0};
    double velocity_mm_s[3] = {0, 0, 0};
    double transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    int buttons = 0;
  };
  static hd::HDCallbackCode servo(void* self);

  PhantomSettings settings_;
  std::string label_;
  DeviceLimits limits_;
  std::shared_ptr<hd::Api> api_;
  hd::HHD hhd_ = hd::kInvalidHandle;
  hd::HDSchedulerHandle callback_ = 0;
  bool running_ = false;
  TripleBuffer<ServoSample> samples_;     // servo → haptic loop
  TripleBuffer<Eigen::Vector3d> forces_;  // haptic loop → servo, device frame [N]
  std::atomic<bool> zero_force_{true};
  std::atomic<unsigned int> servo_error_{0};
  std::atomic<uint64_t> servo_frames_{0};
  uint64_t last_count_ = 0;
  int stale_ = 0;
};

}  // namespace lap::hardware
