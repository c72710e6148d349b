#include "hardware/libusb_transport.h"

#include <libusb-1.0/libusb.h>

#include <string>
#include <utility>

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

/// "BUS-PORT.PORT…" as the kernel names a device's place on the bus.
std::string bus_path(libusb_device* d) {
  std::string path = std::to_string(libusb_get_bus_number(d));
  uint8_t ports[8];
  const int n = libusb_get_port_numbers(d, ports, 8);
  for (int i = 0; i < n; ++i) path += (i == 0 ? "-" : ".") + std::to_string(ports[i]);
  return path;
}

/// The grippers on the bus, each with its device (referenced: unref when done).
std::vector<std::pair<FoundGripper, libusb_device*>> enumerate(libusb_context* context) {
  std::vector<std::pair<FoundGripper, libusb_device*>> out;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor desc{};
    if (libusb_get_device_descriptor(list[i], &desc) != LIBUSB_SUCCESS ||
        desc.idVendor != gripper::kVendorId || desc.idProduct != gripper::kProductId) {
      continue;
    }
    FoundGripper g;
    g.bus_path = bus_path(list[i]);
    libusb_device_handle* h = nullptr;
    if (desc.iSerialNumber != 0 && libusb_open(list[i], &h) == LIBUSB_SUCCESS) {
      unsigned char text[128];
      const int len = libusb_get_string_descriptor_ascii(h, desc.iSerialNumber, text, sizeof(text));
      if (len > 0) g.serial.assign(reinterpret_cast<const char*>(text), static_cast<size_t>(len));
      libusb_close(h);
    }
    out.emplace_back(g, libusb_ref_device(list[i]));
  }
  if (list != nullptr) libusb_free_device_list(list, 1);
  return out;
}

}  // namespace

struct LibusbTransport::Impl {
  GripperSelector selector;
  libusb_context* context = nullptr;
  libusb_device_handle* handle = nullptr;
};

LibusbTransport::LibusbTransport(GripperSelector selector) : impl_(std::make_unique<Impl>()) {
  impl_->selector = std::move(selector);
}

Result<std::vector<FoundGripper>> LibusbTransport::list() {
  libusb_context* context = nullptr;
  if (libusb_init(&context) != LIBUSB_SUCCESS) return diagnostic("libusb could not start");
  std::vector<FoundGripper> found;
  for (auto& [g, device] : enumerate(context)) {
    found.push_back(g);
    libusb_unref_device(device);
  }
  libusb_exit(context);
  return found;
}

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
  auto found = enumerate(impl_->context);
  std::vector<FoundGripper> grippers;
  grippers.reserve(found.size());
  for (const auto& f : found) grippers.push_back(f.first);
  const Result<size_t> chosen = select_gripper(grippers, impl_->selector);
  int rc_open = LIBUSB_ERROR_NOT_FOUND;
  if (chosen.ok()) rc_open = libusb_open(found[chosen.value()].second, &impl_->handle);
  for (auto& f : found) libusb_unref_device(f.second);
  if (!chosen.ok()) return chosen.diagnostics();
  if (rc_open != LIBUSB_SUCCESS) {
    impl_->handle = nullptr;
    return diagnostic("the actuated gripper at " + grippers[chosen.value()].bus_path +
                      " could not be opened: " + libusb_strerror(rc_open) +
                      " (may this user open it? udev rule in hardware/README.md)");
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
