// The OpenHaptics backend: a Phantom Omni / Geomagic Touch through the HD
// API, loaded at run time (HdLibrary). Opening it initialises the device,
// checks its calibration (updating it when the device can do so itself),
// reads its limits (peak and continuous force, stiffness, damping) and
// enables force output. The device's own scheduler is the servo clock: one
// asynchronous callback at the scheduler's highest priority runs every
// tick — begin frame, read pose, velocity and buttons, run the servo tick
// (local force model and safety chain, never DDS), write the force, end
// frame, check for errors.
//
// Faults stop safely: any HD error inside a tick writes zero force and ends
// the loop with the error's description (RunServo returns, fault() says
// what happened); a scheduler that stalls longer than stall_timeout_s is
// counted and its first tick after the stall writes zero, the force then
// ramping back in over resume_ramp_s.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "backends/openhaptics/hd_library.h"
#include "backends/openhaptics/workspace_map.h"
#include "hapsim/servo/device.h"

namespace hapsim::bridge {

struct OpenHapticsConfig {
  std::string library = "libHD.so";  // the HD runtime: a library name or a path
  std::string device_name;           // the HD configuration name; empty: the default device
  WorkspaceMap workspace;
  double calibration_wait_s = 30.0;  // how long to wait for the stylus in its inkwell
  double stall_timeout_s = 0.010;    // a scheduler gap longer than this is a stall
  double resume_ramp_s = 0.5;        // force ramp after a stall [s]
};

// Throws std::invalid_argument naming the bad field.
void ValidateOpenHapticsConfig(const OpenHapticsConfig& config);

struct OpenHapticsCounters {
  std::uint64_t ticks = 0;              // servo callbacks run
  std::uint64_t stalls = 0;             // scheduler gaps beyond stall_timeout_s
  double longest_gap_s = 0.0;           // the longest gap between two callbacks
  bool calibrated_on_open = false;      // the device asked for, and got, a calibration update
  double max_motor_temperature = -1.0;  // hottest motor read, 0..1 of its limit; -1: the device does not report it
  std::uint64_t thermal_derated_ticks = 0;  // ticks whose force was derated for a hot motor
};

// A motor near its temperature limit gets less force before the driver
// stops with HD_WARM_MOTORS: full force up to this share of the limit,
// then linearly less, zero at the limit (read once a second).
inline constexpr double kThermalDerateFrom = 0.8;
// The force scale for the hottest motor at `temperature` (0..1 of its
// limit; negative: not reported, full force).
double ThermalForceScale(double temperature);

class OpenHapticsDevice final : public HapticDevice {
 public:
  // Loads the library and opens the device. Throws DeviceError with a
  // message that says what to do (missing library, no device, calibration).
  explicit OpenHapticsDevice(const OpenHapticsConfig& config);
  ~OpenHapticsDevice() override;
  OpenHapticsDevice(const OpenHapticsDevice&) = delete;
  OpenHapticsDevice& operator=(const OpenHapticsDevice&) = delete;

  std::string Name() const override { return name_; }
  DeviceReading Read(double t_s) override;
  void CommandForce(const Eigen::Vector3d& force_W_N) override;
  DeviceLimits Limits() const override { return limits_; }
  bool RunsOwnServo() const override { return true; }
  // Schedules the servo callback and waits until tick returns false, stop is
  // set or the device faults.
  void RunServo(const std::function<bool(double t_s)>& tick, const std::atomic<bool>& stop) override;

  // Empty unless the device faulted during RunServo.
  std::string fault() const;
  OpenHapticsCounters counters() const;

 private:
  static HDCallbackCode ServoCallback(void* self);
  static HDCallbackCode CalibrationCallback(void* self);
  HDCallbackCode ServoTick();
  std::string ReadStylus();  // into reading_; the HD error, if any
  void TrackSchedulerGap(std::int64_t now_ns);
  void Open();
  void Close();  // stops the scheduler, disables force output and the device
  void Calibrate();
  void ReadLimits();
  void ReadMotorTemperature();
  // The HD error waiting on the library's stack, described; empty if none.
  std::string TakeError();
  void Fail(const std::string& what);
  void EndFrameWithForce(const Eigen::Vector3d& force_D_N);

  OpenHapticsConfig config_;
  std::shared_ptr<const HdLibrary> library_;
  const hd::Functions* hd_ = nullptr;
  HHD device_ = hd::kInvalidHandle;
  std::string name_;
  DeviceLimits limits_;
  bool scheduler_started_ = false;

  // Servo thread (the device's scheduler) only.
  const std::function<bool(double)>* tick_ = nullptr;
  const std::atomic<bool>* stop_ = nullptr;
  DeviceReading reading_;
  Eigen::Vector3d command_W_N_ = Eigen::Vector3d::Zero();
  std::int64_t start_ns_ = 0;
  double resume_scale_ = 1.0;   // < 1 while ramping back after a stall
  double thermal_scale_ = 1.0;  // < 1 while a motor is near its temperature limit
  HDenum calibration_status_ = hd::kCalibrationOk;
  int calibration_style_ = 0;

  // Written by the scheduler, read by anyone.
  std::atomic<bool> done_{false};
  std::atomic<std::uint64_t> ticks_{0}, stalls_{0}, thermal_derated_ticks_{0};
  std::atomic<std::int64_t> last_tick_ns_{0};  // steady clock of the last servo callback
  std::atomic<double> longest_gap_s_{0.0}, max_motor_temperature_{-1.0};
  bool calibrated_on_open_ = false;  // set before the servo runs
  mutable std::mutex fault_mutex_;   // taken only when a fault is recorded or read
  std::string fault_;
};

}  // namespace hapsim::bridge
