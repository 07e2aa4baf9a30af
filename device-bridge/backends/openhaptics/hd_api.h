// Our declarations of the OpenHaptics HD API (Phantom Omni / Geomagic Touch),
// the subset hapsim calls. The vendor's SDK is not in Debian, so nothing here
// includes it: the types, constant values and function signatures below are
// those of the SDK's documented ABI (HD/hdDefines.h, hdDevice.h,
// hdScheduler.h of OpenHaptics 3.x), and the library (libHD.so) is loaded at
// run time (HdLibrary). On Linux the SDK's HDAPIENTRY and HDCALLBACK are the
// default C calling convention.
#pragma once
#include <climits>

extern "C" {

typedef unsigned int HDuint;
typedef unsigned char HDboolean;
typedef unsigned long HDulong;
typedef unsigned short HDushort;
typedef int HDint;
typedef double HDdouble;
typedef unsigned int HDerror;
typedef unsigned int HDenum;
typedef const char* HDstring;
typedef unsigned int HHD;

typedef struct {
  HDerror errorCode;      // an HD_ error code below
  int internalErrorCode;  // the device's own code
  HHD hHD;                // the device current when it happened
} HDErrorInfo;

typedef unsigned int HDCallbackCode;
typedef unsigned long HDSchedulerHandle;
typedef HDCallbackCode (*HDSchedulerCallback)(void* pUserData);
typedef unsigned int HDWaitCode;

}  // extern "C"

namespace hapsim::bridge::hd {

// Error codes.
inline constexpr HDerror kSuccess = 0x0000;
inline constexpr HDerror kInvalidEnum = 0x0100;
inline constexpr HDerror kWarmMotors = 0x0200;
inline constexpr HDerror kExceededMaxForce = 0x0201;
inline constexpr HDerror kExceededMaxForceImpulse = 0x0202;
inline constexpr HDerror kExceededMaxVelocity = 0x0203;
inline constexpr HDerror kForceError = 0x0204;
inline constexpr HDerror kDeviceFault = 0x0300;
inline constexpr HDerror kCommError = 0x0302;

// Parameters (hdGet*v / hdSet*v).
inline constexpr HDenum kCurrentButtons = 0x2000;
inline constexpr HDenum kCurrentPosition = 0x2050;   // 3 doubles [mm], device frame
inline constexpr HDenum kCurrentVelocity = 0x2051;   // 3 doubles [mm/s]
inline constexpr HDenum kCurrentTransform = 0x2052;  // 16 doubles, column-major, translation in mm
inline constexpr HDenum kDeviceModelType = 0x2501;   // string
inline constexpr HDenum kDeviceSerialNumber = 0x2504;
inline constexpr HDenum kCalibrationStyle = 0x2555;           // int: the styles the device supports
inline constexpr HDenum kNominalMaxStiffness = 0x2602;        // N/mm
inline constexpr HDenum kNominalMaxForce = 0x2603;            // N
inline constexpr HDenum kNominalMaxContinuousForce = 0x2604;  // N
inline constexpr HDenum kMotorTemperature = 0x2605;           // per motor, 0..1 of the limit
inline constexpr HDenum kSoftwareVelocityLimit = 0x2606;  // mm/s: past it the driver faults (HD_EXCEEDED_MAX_VELOCITY)
inline constexpr HDenum kNominalMaxDamping = 0x2609;          // N s/mm
inline constexpr HDenum kCurrentForce = 0x2700;               // 3 doubles [N], device frame

// Capabilities (hdEnable / hdDisable).
inline constexpr HDenum kForceOutput = 0x4000;

// Scheduler.
inline constexpr HDushort kMaxSchedulerPriority = USHRT_MAX;
inline constexpr HDCallbackCode kCallbackDone = 0;
inline constexpr HDCallbackCode kCallbackContinue = 1;
inline constexpr HDWaitCode kWaitInfinite = 1;

// Calibration.
inline constexpr HDenum kCalibrationOk = 0x5000;
inline constexpr HDenum kCalibrationNeedsUpdate = 0x5001;
inline constexpr HDenum kCalibrationNeedsManualInput = 0x5002;
inline constexpr HDint kCalibrationEncoderReset = 1 << 0;
inline constexpr HDint kCalibrationAuto = 1 << 1;
inline constexpr HDint kCalibrationInkwell = 1 << 2;

inline constexpr HHD kInvalidHandle = 0xFFFFFFFF;

// The functions hapsim calls, as pointers resolved from the library.
struct Functions {
  HHD (*hdInitDevice)(HDstring config_name);
  void (*hdDisableDevice)(HHD device);
  void (*hdMakeCurrentDevice)(HHD device);
  void (*hdBeginFrame)(HHD device);
  void (*hdEndFrame)(HHD device);
  HDErrorInfo (*hdGetError)();
  HDstring (*hdGetErrorString)(HDerror code);
  void (*hdEnable)(HDenum capability);
  void (*hdDisable)(HDenum capability);
  void (*hdGetIntegerv)(HDenum name, HDint* values);
  void (*hdGetDoublev)(HDenum name, HDdouble* values);
  HDstring (*hdGetString)(HDenum name);
  void (*hdSetDoublev)(HDenum name, const HDdouble* values);
  HDenum (*hdCheckCalibration)();
  void (*hdUpdateCalibration)(HDenum style);
  void (*hdStartScheduler)();
  void (*hdStopScheduler)();
  HDSchedulerHandle (*hdScheduleAsynchronous)(HDSchedulerCallback callback, void* user_data, HDushort priority);
  void (*hdScheduleSynchronous)(HDSchedulerCallback callback, void* user_data, HDushort priority);
  void (*hdUnschedule)(HDSchedulerHandle handle);
  HDboolean (*hdWaitForCompletion)(HDSchedulerHandle handle, HDWaitCode code);
};

}  // namespace hapsim::bridge::hd
