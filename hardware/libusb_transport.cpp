#include "hardware/libusb_transport.h"

#include <libusb-1.0/libusb.h>

#include "hardware/gripper_protocol.h"

namespace lap::hardware {
namespace {

TransferResult map(int rc) {
  switch (rc) {
    case LIBUSB_SUCCESS:
      return TransferResult::kOk;
    case LIBUSB_ERROR_TIMEOUT:
      return TransferResult::kTimeout;
    case LIBUSB_ERROR_PIPE:
      return TransferResult::kStall;
    case LIBUSB_ERROR_NO_DEVICE:
      return TransferResult::kNoDevice;
    default:
      return TransferResult::kError;
  }
}

}  // namespace

struct LibusbTransport::Impl {
  libusb_context* context = nullptr;
  libusb_device_handle* handle = nullptr;
};

LibusbTransport::LibusbTransport() : impl_(std::make_unique<Impl>()) {}

LibusbTransport::~LibusbTransport() {
  close();
  if (impl_->context != nullptr) libusb_exit(impl_->context);
}

Status LibusbTransport::open() {
  close();
  if (impl_->context == nullptr && libusb_init(&impl_->context) != LIBUSB_SUCCESS) {
    impl_->context = nullptr;
    return diagnostic("libusb could not start");
  }
  impl_->handle =
      libusb_open_device_with_vid_pid(impl_->context, gripper::kVendorId, gripper::kProductId);
  if (impl_->handle == nullptr) {
    return diagnostic(
        "no actuated gripper found (USB 1209:4c54); is it plugged in, and may this user "
        "open it (udev rule in hardware/README.md)?");
  }
  libusb_set_auto_detach_kernel_driver(impl_->handle, 1);
  const int rc = libusb_claim_interface(impl_->handle, gripper::kInterface);
  if (rc != LIBUSB_SUCCESS) {
    libusb_close(impl_->handle);
    impl_->handle = nullptr;
    return diagnostic(std::string("the gripper's interface could not be claimed: ") +
                      libusb_strerror(rc));
  }
  return {};
}

void LibusbTransport::close() {
  if (impl_->handle == nullptr) return;
  libusb_release_interface(impl_->handle, gripper::kInterface);
  libusb_close(impl_->handle);
  impl_->handle = nullptr;
}

TransferResult LibusbTransport::read(std::span<uint8_t> buffer, int timeout_ms, size_t* received) {
  *received = 0;
  if (impl_->handle == nullptr) return TransferResult::kNoDevice;
  int got = 0;
  const int rc = libusb_interrupt_transfer(impl_->handle, gripper::kEndpointIn, buffer.data(),
                                           static_cast<int>(buffer.size()), &got,
                                           static_cast<unsigned int>(timeout_ms));
  *received = static_cast<size_t>(got);
  return map(rc);
}

TransferResult LibusbTransport::write(std::span<const uint8_t> bytes, int timeout_ms) {
  if (impl_->handle == nullptr) return TransferResult::kNoDevice;
  int sent = 0;
  // libusb takes a non-const buffer for both directions; OUT transfers do not write to it.
  auto* data = const_cast<unsigned char*>(bytes.data());  // NOLINT(*-const-cast)
  return map(libusb_interrupt_transfer(impl_->handle, gripper::kEndpointOut, data,
                                       static_cast<int>(bytes.size()), &sent,
                                       static_cast<unsigned int>(timeout_ms)));
}

TransferResult LibusbTransport::clear_stall(uint8_t endpoint) {
  if (impl_->handle == nullptr) return TransferResult::kNoDevice;
  return map(libusb_clear_halt(impl_->handle, endpoint));
}

}  // namespace lap::hardware
