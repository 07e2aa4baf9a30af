#include "backends/openhaptics/hd_library.h"

#include <dlfcn.h>

#include <cstdio>

namespace hapsim::bridge {

namespace {

template <class F>
void Resolve(void* handle, const std::string& path, const char* name, F* out) {
  dlerror();  // clear a stale message
  void* symbol = dlsym(handle, name);
  if (!symbol) {
    const char* why = dlerror();
    throw DeviceError("the OpenHaptics library '" + path + "' has no function " + name + " (" +
                      (why ? why : "null symbol") + "): is it the HD runtime of OpenHaptics 3.x?");
  }
  *out = reinterpret_cast<F>(symbol);
}

const char* HdErrorName(HDerror code) {
  switch (code) {
    case hd::kSuccess:
      return "HD_SUCCESS";
    case hd::kInvalidEnum:
      return "HD_INVALID_ENUM";
    case hd::kWarmMotors:
      return "HD_WARM_MOTORS";
    case hd::kExceededMaxForce:
      return "HD_EXCEEDED_MAX_FORCE";
    case hd::kExceededMaxForceImpulse:
      return "HD_EXCEEDED_MAX_FORCE_IMPULSE";
    case hd::kExceededMaxVelocity:
      return "HD_EXCEEDED_MAX_VELOCITY";
    case hd::kForceError:
      return "HD_FORCE_ERROR";
    case hd::kDeviceFault:
      return "HD_DEVICE_FAULT";
    case hd::kCommError:
      return "HD_COMM_ERROR";
    default:
      return "HD error";
  }
}

}  // namespace

std::shared_ptr<const HdLibrary> HdLibrary::Load(const std::string& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw DeviceError("cannot load the OpenHaptics HD library '" + path + "' (" + (why ? why : "unknown error") +
                      "): install the device vendor's OpenHaptics runtime, or give its path with --hd-library");
  }
  std::shared_ptr<HdLibrary> library(new HdLibrary(handle, path));
  hd::Functions& f = library->api_;
  Resolve(handle, path, "hdInitDevice", &f.hdInitDevice);
  Resolve(handle, path, "hdDisableDevice", &f.hdDisableDevice);
  Resolve(handle, path, "hdMakeCurrentDevice", &f.hdMakeCurrentDevice);
  Resolve(handle, path, "hdBeginFrame", &f.hdBeginFrame);
  Resolve(handle, path, "hdEndFrame", &f.hdEndFrame);
  Resolve(handle, path, "hdGetError", &f.hdGetError);
  Resolve(handle, path, "hdGetErrorString", &f.hdGetErrorString);
  Resolve(handle, path, "hdEnable", &f.hdEnable);
  Resolve(handle, path, "hdDisable", &f.hdDisable);
  Resolve(handle, path, "hdGetIntegerv", &f.hdGetIntegerv);
  Resolve(handle, path, "hdGetDoublev", &f.hdGetDoublev);
  Resolve(handle, path, "hdGetString", &f.hdGetString);
  Resolve(handle, path, "hdSetDoublev", &f.hdSetDoublev);
  Resolve(handle, path, "hdCheckCalibration", &f.hdCheckCalibration);
  Resolve(handle, path, "hdUpdateCalibration", &f.hdUpdateCalibration);
  Resolve(handle, path, "hdStartScheduler", &f.hdStartScheduler);
  Resolve(handle, path, "hdStopScheduler", &f.hdStopScheduler);
  Resolve(handle, path, "hdScheduleAsynchronous", &f.hdScheduleAsynchronous);
  Resolve(handle, path, "hdScheduleSynchronous", &f.hdScheduleSynchronous);
  Resolve(handle, path, "hdUnschedule", &f.hdUnschedule);
  Resolve(handle, path, "hdWaitForCompletion", &f.hdWaitForCompletion);
  return library;
}

HdLibrary::~HdLibrary() {
  if (handle_) dlclose(handle_);
}

std::string HdLibrary::Describe(const HDErrorInfo& error) const {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", error.errorCode);
  const char* text = api_.hdGetErrorString ? api_.hdGetErrorString(error.errorCode) : nullptr;
  std::string out = std::string(HdErrorName(error.errorCode)) + " (" + code + ")";
  if (text && *text) out += ": " + std::string(text);
  if (error.internalErrorCode != 0) out += " [device code " + std::to_string(error.internalErrorCode) + "]";
  return out;
}

}  // namespace hapsim::bridge
