// A stand-in for the OpenHaptics HD runtime (libHD.so), so the OpenHaptics
// backend is built, loaded through the same dlopen path and tested on every
// commit without a device or the vendor's SDK. It exports the HD functions
// the backend calls, with the SDK's signatures (checked against our
// declarations below), and simulates an Omni-class stylus:
//  - a scheduler thread at 1 kHz running the scheduled callbacks in priority
//    order, each inside the frames the callbacks open;
//  - a scripted stylus (position-controlled, as a hand that holds its path):
//      HAPSIM_FAKE_HD_SCRIPT=press   from 10 mm above the origin down at
//                                    10 mm/s to 5 mm below it, then held
//                            still   resting 20 mm above the origin
//  - button 2 held for 50 ms at each time of HAPSIM_FAKE_HD_BUTTON_TAPS_MS
//    ("300,900");
//  - device limits of an Omni: 3.3 N peak, 0.88 N continuous, 0.7 N/mm,
//    0.0025 N s/mm, and a software velocity limit of 1200 mm/s
//    (HAPSIM_FAKE_HD_LIMITS="peak,continuous,k,b[,v_mm_s]" overrides);
//  - motors at 0.25 of their temperature limit (HAPSIM_FAKE_HD_TEMPERATURE);
//  - faults, HAPSIM_FAKE_HD_FAULT=
//      no_device            hdInitDevice fails with HD_COMM_ERROR
//      calibration_manual   the stylus must go in its inkwell: never calibrated
//      calibration_update   needs an update, which hdUpdateCalibration does
//      stall:AT_MS:FOR_MS   the scheduler stops calling for FOR_MS at AT_MS
//      force_fault:AT_MS    hdEndFrame reports HD_FORCE_ERROR from AT_MS on
//      no_temperature       HD_MOTOR_TEMPERATURE is an invalid enum
//  - HAPSIM_FAKE_HD_LOG=PATH: every frame that commanded a force, its pose
//    and that force (t_ms,y_mm,fx_N,fy_N,fz_N), written when the device is
//    disabled.
//  - up to four devices at once (handles 1-4), as a lab PC with several
//    styluses: each has its own stylus, limits, frames and log (device k > 1
//    logs to HAPSIM_FAKE_HD_LOG + ".k"), all on one scheduler thread, like
//    the SDK's. The API acts on the current device: the one a frame was
//    begun for, else the one last opened or made current, per thread.
// Environment is read at hdInitDevice; hdDisableDevice closes that device,
// and the last one closed stops the scheduler and forgets everything.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "backends/openhaptics/hd_api.h"

namespace {

namespace hd = hapsim::bridge::hd;
using Clock = std::chrono::steady_clock;

struct Scheduled {
  HDSchedulerHandle handle;
  HDSchedulerCallback callback;
  void* user_data;
  HDushort priority;
  bool synchronous;
  bool done;
};

struct LogRow {
  double t_ms, y_mm, fx, fy, fz;
};

struct Device {
  // Configuration (hdInitDevice).
  std::string script = "press", fault, log_path;
  std::vector<double> taps_ms;
  double limits[5] = {3.3, 0.88, 0.7, 0.0025, 1200.0};
  double temperature = 0.25;
  double stall_at_ms = -1, stall_for_ms = 0, force_fault_at_ms = -1;
  // State.
  bool open = false, calibrated = true, force_enabled = false, in_frame = false, faulted = false;
  bool force_set_in_frame = false;
  double t_ms = 0.0;
  double pos_mm[3] = {0, 0, 0}, vel_mm_s[3] = {0, 0, 0};
  int buttons = 0;
  double pending_force[3] = {0, 0, 0};
  std::vector<LogRow> log;
};

std::mutex g_mutex;  // guards everything below but the scheduler's own loop state
std::condition_variable g_wake;
constexpr HHD kMaxDevices = 4;
Device g_devices[kMaxDevices + 1];  // by handle; [0] unused
thread_local HHD t_current = 1;     // the calling thread's current device
Device& Current() { return g_devices[t_current]; }
bool AnyOpen() {
  return std::any_of(g_devices + 1, g_devices + kMaxDevices + 1, [](const Device& d) { return d.open; });
}
std::vector<HDErrorInfo> g_errors;  // newest last; hdGetError pops from the back
std::vector<Scheduled> g_scheduled;
HDSchedulerHandle g_next_handle = 1;
std::thread g_scheduler;
std::atomic<bool> g_running{false};

void PushError(HDerror code, int internal = 0) { g_errors.push_back(HDErrorInfo{code, internal, 0}); }

double EnvNumber(const std::string& text, std::size_t field) {
  std::size_t start = 0;
  for (std::size_t i = 0; i < field; ++i) start = text.find(':', start) + 1;
  return std::atof(text.c_str() + start);
}

void Configure(Device& d) {
  d = Device{};
  if (const char* s = std::getenv("HAPSIM_FAKE_HD_SCRIPT")) d.script = s;
  if (const char* f = std::getenv("HAPSIM_FAKE_HD_FAULT")) d.fault = f;
  if (const char* l = std::getenv("HAPSIM_FAKE_HD_LOG")) d.log_path = l;
  if (const char* taps = std::getenv("HAPSIM_FAKE_HD_BUTTON_TAPS_MS")) {
    for (const char* p = taps; *p;) {
      d.taps_ms.push_back(std::atof(p));
      const char* comma = std::strchr(p, ',');
      if (!comma) break;
      p = comma + 1;
    }
  }
  if (const char* limits = std::getenv("HAPSIM_FAKE_HD_LIMITS")) {
    std::sscanf(limits, "%lf,%lf,%lf,%lf,%lf", &d.limits[0], &d.limits[1], &d.limits[2], &d.limits[3], &d.limits[4]);
  }
  if (const char* t = std::getenv("HAPSIM_FAKE_HD_TEMPERATURE")) d.temperature = std::atof(t);
  if (d.fault.rfind("stall:", 0) == 0) {
    d.stall_at_ms = EnvNumber(d.fault, 1);
    d.stall_for_ms = EnvNumber(d.fault, 2);
  }
  if (d.fault.rfind("force_fault:", 0) == 0) d.force_fault_at_ms = EnvNumber(d.fault, 1);
  d.calibrated = d.fault != "calibration_manual" && d.fault != "calibration_update";
  d.log.reserve(600000);  // ten minutes of frames: the servo tick never waits for a reallocation
}

// The scripted hand, in the device frame (y up) [mm].
void MoveStylus(Device& d) {
  double y = 20.0, vy = 0.0;
  if (d.script == "press") {
    const double t_s = d.t_ms * 1e-3;
    y = std::max(-5.0, 10.0 - 10.0 * t_s);
    vy = y > -5.0 ? -10.0 : 0.0;
  }
  d.pos_mm[0] = 0.0;
  d.pos_mm[1] = y;
  d.pos_mm[2] = 0.0;
  d.vel_mm_s[0] = 0.0;
  d.vel_mm_s[1] = vy;
  d.vel_mm_s[2] = 0.0;
  d.buttons = 0;
  for (const double tap : d.taps_ms) {
    if (d.t_ms >= tap && d.t_ms < tap + 50.0) d.buttons |= 1 << 1;
  }
}

// One scheduler tick: the callbacks, highest priority first; each may open
// and close frames through the API (which takes g_mutex itself).
void RunCallbacks() {
  std::vector<Scheduled> due;
  {
    std::lock_guard lock(g_mutex);
    for (Device& d : g_devices) {
      if (d.open) MoveStylus(d);
    }
    due = g_scheduled;
  }
  std::stable_sort(due.begin(), due.end(),
                   [](const Scheduled& a, const Scheduled& b) { return a.priority > b.priority; });
  for (const Scheduled& s : due) {
    const HDCallbackCode code = s.callback(s.user_data);
    std::lock_guard lock(g_mutex);
    for (Scheduled& mine : g_scheduled) {
      if (mine.handle == s.handle && (code == hd::kCallbackDone || s.synchronous)) mine.done = true;
    }
  }
  std::lock_guard lock(g_mutex);
  std::erase_if(g_scheduled, [](const Scheduled& s) { return s.done; });
  g_wake.notify_all();
}

void SchedulerLoop() {
  auto next = Clock::now();
  while (g_running.load()) {
    next += std::chrono::microseconds(1000);
    std::this_thread::sleep_until(next);
    double stall_ms = 0.0;
    {
      std::lock_guard lock(g_mutex);
      for (Device& d : g_devices) {  // a stall is the scheduler's: every device misses it
        d.t_ms += 1.0;
        if (d.open && d.stall_at_ms >= 0.0 && d.t_ms >= d.stall_at_ms) {
          stall_ms = std::max(stall_ms, d.stall_for_ms);
          d.stall_at_ms = -1.0;  // once
        }
      }
    }
    if (stall_ms > 0.0) {
      std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(stall_ms));
      next = Clock::now();
      std::lock_guard lock(g_mutex);
      for (Device& d : g_devices) d.t_ms += stall_ms;
    }
    RunCallbacks();
  }
}

void WriteLog(const Device& d) {
  if (d.log_path.empty()) return;
  std::FILE* f = std::fopen(d.log_path.c_str(), "w");
  if (!f) return;
  std::fprintf(f, "t_ms,y_mm,fx_N,fy_N,fz_N\n");
  for (const LogRow& r : d.log) std::fprintf(f, "%.3f,%.6f,%.9g,%.9g,%.9g\n", r.t_ms, r.y_mm, r.fx, r.fy, r.fz);
  std::fclose(f);
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) HHD hdInitDevice(HDstring /*config_name*/) {
  std::lock_guard lock(g_mutex);
  HHD handle = 1;
  while (handle <= kMaxDevices && g_devices[handle].open) ++handle;
  Device probe;
  Configure(probe);
  if (probe.fault == "no_device" || handle > kMaxDevices) {
    PushError(hd::kCommError, 42);
    return hd::kInvalidHandle;
  }
  if (handle > 1 && !probe.log_path.empty()) probe.log_path.append(".").append(std::to_string(handle));
  probe.open = true;
  g_devices[handle] = std::move(probe);
  t_current = handle;
  return handle;
}

__attribute__((visibility("default"))) void hdDisableDevice(HHD handle) {
  bool last;
  {
    std::lock_guard lock(g_mutex);
    if (handle < 1 || handle > kMaxDevices) return;
    WriteLog(g_devices[handle]);
    g_devices[handle] = Device{};
    last = !AnyOpen();
  }
  if (!last) return;
  if (g_running.exchange(false) && g_scheduler.joinable()) g_scheduler.join();
  std::lock_guard lock(g_mutex);
  g_scheduled.clear();
  g_errors.clear();
}

__attribute__((visibility("default"))) void hdMakeCurrentDevice(HHD handle) {
  if (handle >= 1 && handle <= kMaxDevices) t_current = handle;
}

__attribute__((visibility("default"))) void hdBeginFrame(HHD handle) {
  hdMakeCurrentDevice(handle);
  std::lock_guard lock(g_mutex);
  if (Current().in_frame) PushError(0x0400);  // HD_ILLEGAL_BEGIN
  Current().in_frame = true;
}

__attribute__((visibility("default"))) void hdEndFrame(HHD handle) {
  hdMakeCurrentDevice(handle);
  std::lock_guard lock(g_mutex);
  Device& d = Current();
  if (!d.in_frame) PushError(0x0401);  // HD_ILLEGAL_END
  d.in_frame = false;
  const bool fault_now = d.force_fault_at_ms >= 0.0 && d.t_ms >= d.force_fault_at_ms;
  if (fault_now && !d.faulted) {
    d.faulted = true;
    PushError(hd::kForceError, 7);
  }
  double f[3] = {0, 0, 0};
  if (d.force_enabled) std::copy(d.pending_force, d.pending_force + 3, f);
  if (d.force_set_in_frame && d.log.size() < d.log.capacity()) {
    d.log.push_back(LogRow{d.t_ms, d.pos_mm[1], f[0], f[1], f[2]});
  }
  d.force_set_in_frame = false;
}

__attribute__((visibility("default"))) HDErrorInfo hdGetError() {
  std::lock_guard lock(g_mutex);
  if (g_errors.empty()) return HDErrorInfo{hd::kSuccess, 0, 0};
  const HDErrorInfo e = g_errors.back();
  g_errors.pop_back();
  return e;
}

__attribute__((visibility("default"))) HDstring hdGetErrorString(HDerror code) {
  switch (code) {
    case hd::kCommError:
      return "Communication error (fake device: none attached)";
    case hd::kForceError:
      return "Error while commanding force (fake device: injected)";
    case hd::kInvalidEnum:
      return "Invalid enumerant";
    default:
      return "fake HD error";
  }
}

__attribute__((visibility("default"))) void hdEnable(HDenum capability) {
  std::lock_guard lock(g_mutex);
  if (capability == hd::kForceOutput) Current().force_enabled = true;
}

__attribute__((visibility("default"))) void hdDisable(HDenum capability) {
  std::lock_guard lock(g_mutex);
  if (capability == hd::kForceOutput) Current().force_enabled = false;
}

__attribute__((visibility("default"))) void hdGetIntegerv(HDenum name, HDint* values) {
  std::lock_guard lock(g_mutex);
  switch (name) {
    case hd::kCurrentButtons:
      values[0] = Current().buttons;
      return;
    case hd::kCalibrationStyle:
      values[0] = hd::kCalibrationEncoderReset | hd::kCalibrationInkwell;
      return;
    default:
      PushError(hd::kInvalidEnum);
  }
}

__attribute__((visibility("default"))) void hdGetDoublev(HDenum name, HDdouble* values) {
  std::lock_guard lock(g_mutex);
  const Device& d = Current();
  switch (name) {
    case hd::kCurrentPosition:
      std::copy(d.pos_mm, d.pos_mm + 3, values);
      return;
    case hd::kCurrentVelocity:
      std::copy(d.vel_mm_s, d.vel_mm_s + 3, values);
      return;
    case hd::kCurrentTransform: {
      std::fill(values, values + 16, 0.0);
      values[0] = values[5] = values[10] = values[15] = 1.0;  // stylus along the device axes
      std::copy(d.pos_mm, d.pos_mm + 3, values + 12);         // column-major: translation last
      return;
    }
    case hd::kNominalMaxForce:
      values[0] = d.limits[0];
      return;
    case hd::kNominalMaxContinuousForce:
      values[0] = d.limits[1];
      return;
    case hd::kNominalMaxStiffness:
      values[0] = d.limits[2];
      return;
    case hd::kNominalMaxDamping:
      values[0] = d.limits[3];
      return;
    case hd::kSoftwareVelocityLimit:
      values[0] = d.limits[4];
      return;
    case hd::kMotorTemperature:
      if (d.fault == "no_temperature") break;
      std::fill(values, values + 6, 0.0);
      values[0] = values[2] = 0.25;
      values[1] = d.temperature;  // the motor the test heats
      return;
    default:
      break;
  }
  PushError(hd::kInvalidEnum);
}

__attribute__((visibility("default"))) HDstring hdGetString(HDenum name) {
  return name == hd::kDeviceModelType ? "hapsim fake Omni" : "";
}

__attribute__((visibility("default"))) void hdSetDoublev(HDenum name, const HDdouble* values) {
  std::lock_guard lock(g_mutex);
  if (name != hd::kCurrentForce) {
    PushError(hd::kInvalidEnum);
    return;
  }
  std::copy(values, values + 3, Current().pending_force);
  Current().force_set_in_frame = true;
}

__attribute__((visibility("default"))) HDenum hdCheckCalibration() {
  std::lock_guard lock(g_mutex);
  if (Current().calibrated) return hd::kCalibrationOk;
  return Current().fault == "calibration_manual" ? hd::kCalibrationNeedsManualInput : hd::kCalibrationNeedsUpdate;
}

__attribute__((visibility("default"))) void hdUpdateCalibration(HDenum style) {
  std::lock_guard lock(g_mutex);
  if (Current().fault == "calibration_update" && style == static_cast<HDenum>(hd::kCalibrationEncoderReset)) {
    Current().calibrated = true;
  }
}

__attribute__((visibility("default"))) void hdStartScheduler() {
  if (g_running.exchange(true)) return;
  g_scheduler = std::thread(SchedulerLoop);
}

__attribute__((visibility("default"))) void hdStopScheduler() {
  if (g_running.exchange(false) && g_scheduler.joinable()) g_scheduler.join();
}

__attribute__((visibility("default"))) HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback callback,
                                                                                void* user_data, HDushort priority) {
  std::lock_guard lock(g_mutex);
  const HDSchedulerHandle handle = g_next_handle++;
  g_scheduled.push_back(Scheduled{handle, callback, user_data, priority, false, false});
  return handle;
}

__attribute__((visibility("default"))) void hdScheduleSynchronous(HDSchedulerCallback callback, void* user_data,
                                                                  HDushort priority) {
  std::unique_lock lock(g_mutex);
  const HDSchedulerHandle handle = g_next_handle++;
  g_scheduled.push_back(Scheduled{handle, callback, user_data, priority, true, false});
  g_wake.wait(lock, [&] {
    return std::none_of(g_scheduled.begin(), g_scheduled.end(), [&](const Scheduled& s) { return s.handle == handle; });
  });
}

__attribute__((visibility("default"))) void hdUnschedule(HDSchedulerHandle handle) {
  std::lock_guard lock(g_mutex);
  std::erase_if(g_scheduled, [&](const Scheduled& s) { return s.handle == handle; });
}

__attribute__((visibility("default"))) HDboolean hdWaitForCompletion(HDSchedulerHandle handle, HDWaitCode) {
  std::unique_lock lock(g_mutex);
  g_wake.wait(lock, [&] {
    return !g_running.load() ||
           std::none_of(g_scheduled.begin(), g_scheduled.end(), [&](const Scheduled& s) { return s.handle == handle; });
  });
  return 0;
}

}  // extern "C"

// The fake's functions have exactly the signatures the backend resolves.
static_assert(std::is_same_v<decltype(&hdInitDevice), decltype(hd::Functions::hdInitDevice)>);
static_assert(std::is_same_v<decltype(&hdGetError), decltype(hd::Functions::hdGetError)>);
static_assert(std::is_same_v<decltype(&hdScheduleAsynchronous), decltype(hd::Functions::hdScheduleAsynchronous)>);
static_assert(std::is_same_v<decltype(&hdGetDoublev), decltype(hd::Functions::hdGetDoublev)>);
static_assert(std::is_same_v<decltype(&hdSetDoublev), decltype(hd::Functions::hdSetDoublev)>);
static_assert(std::is_same_v<decltype(&hdWaitForCompletion), decltype(hd::Functions::hdWaitForCompletion)>);
