#pragma once
/// \file
/// The part of OpenHaptics' HD API (3D Systems) the PHANToM driver uses, resolved at run time
/// from libHD.so with dlopen/dlsym, so laptrainer needs neither the headers nor the library to
/// build and run. Types and constants are the HD API's published values (hdDefines.h).

#include <cstdint>
#include <memory>
#include <string>

#include "core/result.h"

namespace lap::hardware::hd {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDSchedulerHandle = unsigned long;
using HDCallbackCode = unsigned int;
using HDSchedulerCallback = HDCallbackCode (*)(void*);

struct HDErrorInfo {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
};

inline constexpr HHD kInvalidHandle = 0xFFFFFFFFU;
inline constexpr HDerror kSuccess = 0x0000;
inline constexpr HDCallbackCode kCallbackDone = 0;
inline constexpr HDCallbackCode kCallbackContinue = 1;
inline constexpr HDenum kCurrentButtons = 0x2000;
inline constexpr HDenum kCurrentPosition = 0x2050;      ///< mm
inline constexpr HDenum kCurrentVelocity = 0x2051;      ///< mm/s
inline constexpr HDenum kCurrentTransform = 0x2052;     ///< 4x4 column-major, translation in mm
inline constexpr HDenum kNominalMaxStiffness = 0x2602;  ///< N/mm
inline constexpr HDenum kNominalMaxForce = 0x2603;      ///< N
inline constexpr HDenum kCurrentForce = 0x2700;         ///< N
inline constexpr HDenum kForceOutput = 0x4000;
inline constexpr HDenum kMaxForceClamping = 0x4001;
inline constexpr HDenum kForceRamping = 0x4002;
inline constexpr HDenum kCalibrationOk = 0x5000;
inline constexpr HDenum kCalibrationNeedsUpdate = 0x5001;
inline constexpr HDenum kCalibrationNeedsManualInput = 0x5002;
inline constexpr unsigned short kMaxSchedulerPriority = 0xFFFF;

/// The loaded library: function pointers, and the one scheduler all devices share.
struct Api {
  void* handle = nullptr;
  HHD (*hdInitDevice)(const char*) = nullptr;
  void (*hdDisableDevice)(HHD) = nullptr;
  void (*hdMakeCurrentDevice)(HHD) = nullptr;
  HDErrorInfo (*hdGetError)() = nullptr;
  void (*hdEnable)(HDenum) = nullptr;
  HDenum (*hdCheckCalibration)() = nullptr;
  void (*hdUpdateCalibration)(HDenum) = nullptr;
  void (*hdGetDoublev)(HDenum, double*) = nullptr;
  void (*hdGetIntegerv)(HDenum, int*) = nullptr;
  void (*hdSetDoublev)(HDenum, const double*) = nullptr;
  void (*hdBeginFrame)(HHD) = nullptr;
  void (*hdEndFrame)(HHD) = nullptr;
  HDSchedulerHandle (*hdScheduleAsynchronous)(HDSchedulerCallback, void*, unsigned short) = nullptr;
  void (*hdUnschedule)(HDSchedulerHandle) = nullptr;
  void (*hdStartScheduler)() = nullptr;
  void (*hdStopScheduler)() = nullptr;
  int scheduler_users = 0;  ///< devices whose callbacks run

  Api() = default;
  Api(const Api&) = delete;
  Api& operator=(const Api&) = delete;
  Api(Api&&) = delete;
  Api& operator=(Api&&) = delete;
  ~Api();
};

/// Loads `library` (a name dlopen searches for, or a path) once per process and path; the
/// devices share it. On failure, a diagnostic naming what to install or the missing symbols.
[[nodiscard]] Result<std::shared_ptr<Api>> load_api(const std::string& library);

}  // namespace lap::hardware::hd
