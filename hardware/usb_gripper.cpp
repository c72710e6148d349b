#include "hardware/usb_gripper.h"

#include <chrono>
#include <utility>

namespace lap::hardware {
namespace {

using Clock = std::chrono::steady_clock;

int rank(DeviceStatus s) {
  switch (s) {
    case DeviceStatus::kOk:
      return 0;
    case DeviceStatus::kFinished:
      return 1;
    case DeviceStatus::kDisconnected:
      return 2;
    case DeviceStatus::kError:
      return 3;
  }
  return 3;
}

}  // namespace

UsbGripper::UsbGripper(std::unique_ptr<UsbTransport> transport, const UsbGripperSettings& settings)
    : transport_(std::move(transport)), settings_(settings), opening_(0.0), squeeze_(0.0) {}

UsbGripper::~UsbGripper() { stop(); }

void UsbGripper::set_error(DeviceStatus status, const std::string& why) {
  status_.store(static_cast<uint8_t>(status));
  const std::lock_guard<std::mutex> lock(error_mutex_);
  last_error_ = why;
}

Status UsbGripper::start() {
  if (const Status opened = transport_->open(); !opened.ok()) {
    return diagnostic("gripper: " + opened.message());
  }
  status_.store(static_cast<uint8_t>(DeviceStatus::kDisconnected));
  running_.store(true);
  io_ = std::thread([this] { io_loop(); });
  const auto deadline = Clock::now() + std::chrono::milliseconds(settings_.start_timeout_ms);
  while (Clock::now() < deadline && reports_.load() == 0 &&
         status_.load() != static_cast<uint8_t>(DeviceStatus::kError)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (status_.load() != static_cast<uint8_t>(DeviceStatus::kOk)) {
    const std::string detail = last_error();
    stop();
    return diagnostic("gripper: " + (detail.empty()
                                         ? "no valid state report within " +
                                               std::to_string(settings_.start_timeout_ms) + " ms"
                                         : detail));
  }
  return {};
}

void UsbGripper::stop() {
  if (!running_.exchange(false)) return;
  io_.join();
  // Motor off and zero squeeze, then let go of the device.
  gripper::CommandReport off;
  const auto bytes = gripper::encode(off);
  (void)transport_->write(bytes, settings_.write_timeout_ms);
  transport_->close();
}

void UsbGripper::io_loop() {
  std::array<uint8_t, 64> buffer{};
  bool connected = true;
  int bad_run = 0;
  uint16_t sequence = 0;
  auto last_report = Clock::now();
  auto last_attempt = Clock::now();
  while (running_.load(std::memory_order_relaxed)) {
    if (!connected) {
      if (Clock::now() - last_attempt <
          std::chrono::milliseconds(settings_.reconnect_interval_ms)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      last_attempt = Clock::now();
      if (!transport_->open().ok()) continue;
      connected = true;
      ++reconnects_;
      last_report = Clock::now();
    }
    size_t got = 0;
    const TransferResult r = transport_->read(buffer, settings_.read_timeout_ms, &got);
    switch (r) {
      case TransferResult::kOk:
        if (take_report(std::span<const uint8_t>(buffer).first(got), &bad_run)) {
          last_report = Clock::now();
        }
        break;
      case TransferResult::kTimeout:
        ++timeouts_;
        break;
      case TransferResult::kStall:
        ++stalls_;
        (void)transport_->clear_stall(gripper::kEndpointIn);
        break;
      case TransferResult::kNoDevice:
        set_error(DeviceStatus::kDisconnected, "unplugged");
        transport_->close();
        connected = false;
        continue;
      case TransferResult::kError:
        set_error(DeviceStatus::kError, "USB transfer error");
        break;
    }
    if (Clock::now() - last_report > std::chrono::milliseconds(settings_.stale_after_ms) &&
        status_.load() == static_cast<uint8_t>(DeviceStatus::kOk)) {
      set_error(DeviceStatus::kDisconnected,
                "no state report for " + std::to_string(settings_.stale_after_ms) + " ms");
    }
    connected = send_squeeze(&sequence);
  }
}

bool UsbGripper::take_report(std::span<const uint8_t> bytes, int* bad_run) {
  const Result<gripper::StateReport> report = gripper::decode_state(bytes);
  if (!report.ok()) {
    ++malformed_;
    if (++*bad_run > settings_.max_bad_reports) {
      set_error(DeviceStatus::kError, std::to_string(*bad_run) + " malformed reports in a row (" +
                                          report.message() + ")");
    }
    return false;
  }
  *bad_run = 0;
  if ((report->flags & gripper::kFlagCalibrated) == 0) {
    set_error(DeviceStatus::kError, "not calibrated: close the handle fully once so the jaws home");
  } else if ((report->flags & gripper::kFlagMotorFault) != 0) {
    set_error(DeviceStatus::kError, "the motor reports a fault");
  } else if ((report->flags & gripper::kFlagOverTemperature) != 0) {
    set_error(DeviceStatus::kError, "the motor is too hot");
  } else {
    opening_.publish(gripper::opening_rad(settings_.calibration, report->encoder_counts));
    // A report does not undo a squeeze that cannot be sent (send_squeeze).
    if (failed_writes_ < settings_.max_failed_writes) {
      status_.store(static_cast<uint8_t>(DeviceStatus::kOk));
    }
  }
  ++reports_;  // after the status, so start() sees the report's verdict
  return true;
}

bool UsbGripper::send_squeeze(uint16_t* sequence) {
  gripper::CommandReport c;
  c.motor_enabled = true;
  c.sequence = ++*sequence;
  c.squeeze_mn = gripper::squeeze_mn(settings_.calibration, squeeze_.latest());
  const TransferResult w = transport_->write(gripper::encode(c), settings_.write_timeout_ms);
  if (w == TransferResult::kNoDevice) {
    set_error(DeviceStatus::kDisconnected, "unplugged");
    transport_->close();
    return false;
  }
  if (w == TransferResult::kOk) {
    failed_writes_ = 0;
    return true;
  }
  if (w == TransferResult::kStall) {
    ++stalls_;
    (void)transport_->clear_stall(gripper::kEndpointOut);
  }
  if (++failed_writes_ == settings_.max_failed_writes) {
    set_error(DeviceStatus::kError,
              std::to_string(failed_writes_) + " squeeze commands in a row not sent (" +
                  (w == TransferResult::kStall ? "the OUT endpoint stays stalled"
                                               : "OUT transfers failing") +
                  "): the motor may be holding its last squeeze");
  }
  return true;
}

DeviceStatus UsbGripper::read(double* opening_rad) noexcept {
  *opening_rad = opening_.latest();
  return static_cast<DeviceStatus>(status_.load(std::memory_order_relaxed));
}

void UsbGripper::write(double squeeze_n) noexcept { squeeze_.publish(squeeze_n); }

UsbGripperCounters UsbGripper::counters() const {
  return {reports_.load(), malformed_.load(), stalls_.load(), timeouts_.load(), reconnects_.load()};
}

std::string UsbGripper::last_error() const {
  const std::lock_guard<std::mutex> lock(error_mutex_);
  return last_error_;
}

ArmWithGripper::ArmWithGripper(std::unique_ptr<HapticDevice> arm,
                               std::unique_ptr<UsbGripper> gripper)
    : arm_(std::move(arm)),
      gripper_(std::move(gripper)),
      limits_(arm_->limits()),
      name_(std::string(arm_->name()) + "+gripper") {
  limits_.max_squeeze_n = gripper_->settings().calibration.max_squeeze_n;
}

Status ArmWithGripper::start() {
  if (Status s = arm_->start(); !s.ok()) return s;
  if (Status s = gripper_->start(); !s.ok()) {
    arm_->stop();
    return s;
  }
  return {};
}

void ArmWithGripper::stop() {
  gripper_->stop();
  arm_->stop();
}

DeviceStatus ArmWithGripper::read(int64_t tick, double period_s, DeviceSample* out) noexcept {
  const DeviceStatus a = arm_->read(tick, period_s, out);
  double opening = 0.0;
  const DeviceStatus g = gripper_->read(&opening);
  out->gripper_angle_rad = opening;
  return rank(g) > rank(a) ? g : a;
}

DeviceStatus ArmWithGripper::write(const DeviceCommand& command) noexcept {
  gripper_->write(command.squeeze_n);
  return arm_->write(command);
}

std::string ArmWithGripper::last_error() const {
  const std::string a = arm_->last_error();
  const std::string g = gripper_->last_error();
  return a.empty() ? g : g.empty() ? a : a + "; " + g;
}

}  // namespace lap::hardware
