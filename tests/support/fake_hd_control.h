#pragma once
/// \file
/// The fake libHD.so's test controls (fake_hd.cpp), looked up in the same loaded library the
/// PHANToM driver uses (dlopen of one path returns one library).

#include <dlfcn.h>

#include <Eigen/Core>

namespace lap::test {

struct FakeHd {
  void* handle = dlopen(LAP_FAKE_HD, RTLD_NOW | RTLD_LOCAL);
  FakeHd() = default;
  FakeHd(const FakeHd&) = delete;
  FakeHd& operator=(const FakeHd&) = delete;
  FakeHd(FakeHd&&) = delete;
  FakeHd& operator=(FakeHd&&) = delete;
  ~FakeHd() {
    if (handle != nullptr) dlclose(handle);
  }
  template <typename F>
  F* fn(const char* name) const {
    return reinterpret_cast<F*>(dlsym(handle, name));  // NOLINT(*-reinterpret-cast)
  }
  void set_state(unsigned h, Eigen::Vector3d p_mm, Eigen::Vector3d v_mm_s, int buttons) const {
    fn<void(unsigned, const double*, const double*, int)>("fake_hd_set_state")(
        h, p_mm.data(), v_mm_s.data(), buttons);
  }
  [[nodiscard]] Eigen::Vector3d force(unsigned h) const {
    Eigen::Vector3d f;
    fn<void(unsigned, double*)>("fake_hd_force")(h, f.data());
    return f;
  }
  void unplug(unsigned h, bool unplugged) const {
    fn<void(unsigned, int)>("fake_hd_unplug")(h, unplugged ? 1 : 0);
  }
  void set_servo_error(unsigned code) const { fn<void(unsigned)>("fake_hd_set_servo_error")(code); }
  void set_calibration(unsigned c) const { fn<void(unsigned)>("fake_hd_set_calibration")(c); }
  [[nodiscard]] bool force_output_enabled(unsigned h) const {
    return fn<int(unsigned)>("fake_hd_force_output_enabled")(h) != 0;
  }
  void reset() const { fn<void()>("fake_hd_reset")(); }
};

}  // namespace lap::test
