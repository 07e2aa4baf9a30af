#include "backends/openhaptics_device.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "hapsim/common/clock.h"

namespace hapsim::bridge {

namespace {

// HD stiffness and damping are per millimetre.
constexpr double kPerMmToPerM = 1e3;

bool IsFinitePositive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void ValidateOpenHapticsConfig(const OpenHapticsConfig& c) {
  if (c.library.empty()) throw std::invalid_argument("--hd-library must name the OpenHaptics HD library");
  if (!IsFinitePositive(c.workspace.scale) || c.workspace.scale > 100.0) {
    throw std::invalid_argument("--workspace-scale must be in (0, 100] (world metres per device metre)");
  }
  if (!c.workspace.offset_W_m.allFinite() || c.workspace.offset_W_m.norm() > 10.0) {
    throw std::invalid_argument("--workspace-offset-mm must be finite and within 10 m of the origin");
  }
  if (!(c.calibration_wait_s >= 0.0 && c.calibration_wait_s <= 600.0)) {
    throw std::invalid_argument("--hd-calibration-wait-s must be in [0, 600]");
  }
  if (!(c.stall_timeout_s >= 0.002 && c.stall_timeout_s <= 1.0)) {
    throw std::invalid_argument("--hd-stall-ms must be in [2, 1000]");
  }
  if (!(c.resume_ramp_s >= 0.0 && c.resume_ramp_s <= 10.0))
    throw std::invalid_argument("resume ramp must be in [0, 10] s");
}

OpenHapticsDevice::OpenHapticsDevice(const OpenHapticsConfig& config) : config_(config) {
  ValidateOpenHapticsConfig(config_);
  library_ = HdLibrary::Load(config_.library);
  hd_ = &library_->api();
  try {
    Open();
  } catch (...) {
    Close();  // a half-opened device: its scheduler must stop before the library goes
    throw;
  }
}

OpenHapticsDevice::~OpenHapticsDevice() { Close(); }

void OpenHapticsDevice::Close() {
  if (scheduler_started_) hd_->hdStopScheduler();
  scheduler_started_ = false;
  if (device_ != hd::kInvalidHandle) {
    hd_->hdDisable(hd::kForceOutput);
    hd_->hdDisableDevice(device_);
  }
  device_ = hd::kInvalidHandle;
}

std::string OpenHapticsDevice::TakeError() {
  const HDErrorInfo error = hd_->hdGetError();
  if (error.errorCode == hd::kSuccess) return {};
  std::string text = library_->Describe(error);
  while (hd_->hdGetError().errorCode != hd::kSuccess) {  // older errors of the same call: the newest says it
  }
  return text;
}

void OpenHapticsDevice::Open() {
  const std::string which = config_.device_name.empty() ? "the default haptic device" : "'" + config_.device_name + "'";
  device_ = hd_->hdInitDevice(config_.device_name.empty() ? nullptr : config_.device_name.c_str());
  if (const std::string error = TakeError(); !error.empty() || device_ == hd::kInvalidHandle) {
    device_ = hd::kInvalidHandle;
    throw DeviceError("cannot open " + which + " through " + library_->path() + ": " +
                      (error.empty() ? "no device" : error) +
                      ". Is it plugged in and configured (the vendor's Touch Setup / Phantom Configuration)?");
  }
  const HDstring model = hd_->hdGetString(hd::kDeviceModelType);
  name_ = std::string("openhaptics:") + (model && *model ? model : "device");
  TakeError();  // a device without a model string is still usable
  ReadLimits();
  hd_->hdStartScheduler();
  scheduler_started_ = true;
  if (const std::string error = TakeError(); !error.empty())
    throw DeviceError("cannot start the HD scheduler: " + error);
  Calibrate();
  hd_->hdEnable(hd::kForceOutput);
  if (const std::string error = TakeError(); !error.empty()) throw DeviceError("cannot enable force output: " + error);
}

void OpenHapticsDevice::ReadLimits() {
  HDdouble force = 0, continuous = 0, stiffness = 0, damping = 0, velocity_mm_s = 0;
  hd_->hdGetDoublev(hd::kNominalMaxForce, &force);
  hd_->hdGetDoublev(hd::kNominalMaxContinuousForce, &continuous);
  hd_->hdGetDoublev(hd::kNominalMaxStiffness, &stiffness);
  hd_->hdGetDoublev(hd::kNominalMaxDamping, &damping);
  if (const std::string error = TakeError(); !error.empty()) {
    throw DeviceError("cannot read the device's force limits: " + error);
  }
  // The driver's own velocity check (it faults past it); not every runtime says.
  hd_->hdGetDoublev(hd::kSoftwareVelocityLimit, &velocity_mm_s);
  if (!TakeError().empty()) velocity_mm_s = 0;
  // In world units a scaled workspace moves the tool `scale` times as fast.
  limits_.max_velocity_m_per_s = IsFinitePositive(velocity_mm_s) ? config_.workspace.scale * velocity_mm_s * 1e-3 : 0.0;
  // A limit the device does not state (0 or garbage) stays unknown: ours apply.
  limits_.max_force_N = IsFinitePositive(force) ? force : 0.0;
  limits_.max_continuous_force_N = IsFinitePositive(continuous) ? continuous : 0.0;
  limits_.max_stiffness_N_per_m =
      IsFinitePositive(stiffness) ? config_.workspace.WorldCap(stiffness * kPerMmToPerM) : 0.0;
  limits_.max_damping_Ns_per_m = IsFinitePositive(damping) ? config_.workspace.WorldCap(damping * kPerMmToPerM) : 0.0;
}

// hdCheckCalibration and hdUpdateCalibration run inside a frame, on the
// scheduler (as the SDK's calibration example does).
HDCallbackCode OpenHapticsDevice::CalibrationCallback(void* self) {
  auto& d = *static_cast<OpenHapticsDevice*>(self);
  d.hd_->hdBeginFrame(d.device_);
  d.calibration_status_ = d.hd_->hdCheckCalibration();
  if (d.calibration_status_ == hd::kCalibrationNeedsUpdate) {
    d.hd_->hdUpdateCalibration(static_cast<HDenum>(d.calibration_style_));
    d.calibrated_on_open_ = true;
    d.calibration_status_ = d.hd_->hdCheckCalibration();
  }
  d.hd_->hdEndFrame(d.device_);
  return hd::kCallbackDone;
}

void OpenHapticsDevice::Calibrate() {
  HDint styles = 0;
  hd_->hdGetIntegerv(hd::kCalibrationStyle, &styles);
  TakeError();  // a device that does not say its styles is asked with none
  // The style the device can do by itself first, as the SDK's examples choose.
  calibration_style_ = (styles & hd::kCalibrationEncoderReset) ? hd::kCalibrationEncoderReset
                       : (styles & hd::kCalibrationInkwell)    ? hd::kCalibrationInkwell
                       : (styles & hd::kCalibrationAuto)       ? hd::kCalibrationAuto
                                                               : 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(config_.calibration_wait_s);
  for (;;) {
    hd_->hdScheduleSynchronous(&CalibrationCallback, this, hd::kMaxSchedulerPriority);
    if (const std::string error = TakeError(); !error.empty()) throw DeviceError("cannot check calibration: " + error);
    if (calibration_status_ == hd::kCalibrationOk) return;
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  throw DeviceError(calibration_status_ == hd::kCalibrationNeedsManualInput
                        ? "the haptic device needs calibrating: put the stylus in its inkwell (or run the vendor's "
                          "calibration tool) and start again"
                        : "the haptic device's calibration did not complete");
}

void OpenHapticsDevice::RunServo(const std::function<bool(double)>& tick, const std::atomic<bool>& stop) {
  tick_ = &tick;
  stop_ = &stop;
  done_ = false;
  start_ns_ = common::SteadyNowNs();
  last_tick_ns_.store(0);
  const HDSchedulerHandle handle = hd_->hdScheduleAsynchronous(&ServoCallback, this, hd::kMaxSchedulerPriority);
  if (const std::string error = TakeError(); !error.empty()) {
    Fail("cannot schedule the servo callback: " + error);
    return;
  }
  // The scheduler runs the loop. This thread waits, and ends it itself only
  // when asked to stop while the scheduler has stopped calling (a stall).
  constexpr std::int64_t kGiveUpAfterStopNs = 100'000'000;
  while (!done_.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::int64_t last_ns = last_tick_ns_.load(std::memory_order_relaxed);
    if (stop.load() && common::SteadyNowNs() - (last_ns ? last_ns : start_ns_) > kGiveUpAfterStopNs) {
      hd_->hdUnschedule(handle);
      TakeError();
      return;
    }
  }
  hd_->hdWaitForCompletion(handle, hd::kWaitInfinite);
  TakeError();
}

HDCallbackCode OpenHapticsDevice::ServoCallback(void* self) {
  return static_cast<OpenHapticsDevice*>(self)->ServoTick();
}

HDCallbackCode OpenHapticsDevice::ServoTick() {
  const std::int64_t now_ns = common::SteadyNowNs();
  hd_->hdBeginFrame(device_);
  if (const std::string error = ReadStylus(); !error.empty()) {
    EndFrameWithForce(Eigen::Vector3d::Zero());
    Fail("the haptic device failed while reading the stylus: " + error);
    return hd::kCallbackDone;
  }
  TrackSchedulerGap(now_ns);
  const bool go = !stop_->load(std::memory_order_relaxed) &&
                  (*tick_)(static_cast<double>(now_ns - start_ns_) * 1e-9);  // Read + CommandForce
  ticks_.fetch_add(1, std::memory_order_relaxed);
  if (ticks_.load(std::memory_order_relaxed) % 1000 == 1) ReadMotorTemperature();
  const Eigen::Vector3d force_D_N =
      go && command_W_N_.allFinite()
          ? Eigen::Vector3d(resume_scale_ * thermal_scale_ * config_.workspace.Force_D_N(command_W_N_))
          : Eigen::Vector3d::Zero();
  if (thermal_scale_ < 1.0 && command_W_N_.squaredNorm() > 0.0)
    thermal_derated_ticks_.fetch_add(1, std::memory_order_relaxed);
  EndFrameWithForce(force_D_N);
  if (const std::string error = TakeError(); !error.empty()) {
    hd_->hdBeginFrame(device_);  // one more frame, to leave the motors at zero
    EndFrameWithForce(Eigen::Vector3d::Zero());
    TakeError();
    Fail("the haptic device faulted while rendering force: " + error);
    return hd::kCallbackDone;
  }
  if (!go) {
    done_ = true;
    return hd::kCallbackDone;
  }
  return hd::kCallbackContinue;
}

std::string OpenHapticsDevice::ReadStylus() {
  HDdouble transform[16], velocity[3];
  HDint buttons = 0;
  hd_->hdGetDoublev(hd::kCurrentTransform, transform);
  hd_->hdGetDoublev(hd::kCurrentVelocity, velocity);
  hd_->hdGetIntegerv(hd::kCurrentButtons, &buttons);
  if (std::string error = TakeError(); !error.empty()) return error;
  const Eigen::Map<const Eigen::Matrix4d> T_D(transform);  // column-major, like Eigen
  reading_.tip_W_m = config_.workspace.Position_W_m(T_D.block<3, 1>(0, 3));
  reading_.orientation_W = config_.workspace.Orientation_W(T_D.block<3, 3>(0, 0));
  reading_.velocity_W_m_per_s =
      config_.workspace.Velocity_W_m_per_s(Eigen::Vector3d(velocity[0], velocity[1], velocity[2]));
  reading_.buttons = static_cast<std::uint32_t>(buttons);
  return {};
}

// A stalled scheduler: the first tick after it commands zero, then ramps.
void OpenHapticsDevice::TrackSchedulerGap(std::int64_t now_ns) {
  const std::int64_t last_ns = last_tick_ns_.load(std::memory_order_relaxed);
  if (last_ns != 0) {
    const double gap_s = static_cast<double>(now_ns - last_ns) * 1e-9;
    if (gap_s > longest_gap_s_.load(std::memory_order_relaxed)) longest_gap_s_.store(gap_s, std::memory_order_relaxed);
    if (gap_s > config_.stall_timeout_s) {
      stalls_.fetch_add(1, std::memory_order_relaxed);
      resume_scale_ = 0.0;
    } else if (resume_scale_ < 1.0) {
      resume_scale_ = config_.resume_ramp_s > 0.0 ? std::min(1.0, resume_scale_ + gap_s / config_.resume_ramp_s) : 1.0;
    }
  }
  last_tick_ns_.store(now_ns, std::memory_order_relaxed);
}

void OpenHapticsDevice::EndFrameWithForce(const Eigen::Vector3d& force_D_N) {
  const HDdouble force[3] = {force_D_N.x(), force_D_N.y(), force_D_N.z()};
  hd_->hdSetDoublev(hd::kCurrentForce, force);
  hd_->hdEndFrame(device_);
}

void OpenHapticsDevice::ReadMotorTemperature() {
  HDdouble temperatures[6] = {-1, -1, -1, -1, -1, -1};
  hd_->hdGetDoublev(hd::kMotorTemperature, temperatures);
  if (!TakeError().empty()) return;  // not every device reports it
  const double hottest = *std::max_element(std::begin(temperatures), std::end(temperatures));
  max_motor_temperature_.store(std::max(hottest, max_motor_temperature_.load(std::memory_order_relaxed)),
                               std::memory_order_relaxed);
  thermal_scale_ = ThermalForceScale(hottest);
}

void OpenHapticsDevice::Fail(const std::string& what) {
  {
    std::lock_guard lock(fault_mutex_);
    if (fault_.empty()) fault_ = what;
  }
  done_ = true;
}

double ThermalForceScale(double temperature) {
  if (!(temperature > kThermalDerateFrom)) return 1.0;  // cool, or not reported (negative, NaN)
  return std::clamp((1.0 - temperature) / (1.0 - kThermalDerateFrom), 0.0, 1.0);
}

DeviceReading OpenHapticsDevice::Read(double /*t_s*/) { return reading_; }

void OpenHapticsDevice::CommandForce(const Eigen::Vector3d& force_W_N) { command_W_N_ = force_W_N; }

std::string OpenHapticsDevice::fault() const {
  std::lock_guard lock(fault_mutex_);
  return fault_;
}

OpenHapticsCounters OpenHapticsDevice::counters() const {
  OpenHapticsCounters c;
  c.ticks = ticks_.load();
  c.stalls = stalls_.load();
  c.longest_gap_s = longest_gap_s_.load();
  c.calibrated_on_open = calibrated_on_open_;
  c.max_motor_temperature = max_motor_temperature_.load();
  c.thermal_derated_ticks = thermal_derated_ticks_.load();
  return c;
}

}  // namespace hapsim::bridge
