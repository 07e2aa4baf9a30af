// The OpenHaptics backend against the fake HD runtime (tests/device-bridge/
// fake_hd), loaded through the same dlopen path as the vendor's libHD.so:
// clear errors for every way a device cannot start, units and axes
// converted in both directions, and every fault during the servo loop
// ending in zero force.
#include "backends/openhaptics_device.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "hapsim/servo/force_safety.h"

namespace hapsim::bridge {
namespace {

struct FakeFrame {
  double t_ms, y_mm, fx, fy, fz;
};

// Sets the fake's environment for the next device opened.
class FakeHdTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name : {"HAPSIM_FAKE_HD_SCRIPT", "HAPSIM_FAKE_HD_FAULT", "HAPSIM_FAKE_HD_LIMITS",
                             "HAPSIM_FAKE_HD_BUTTON_TAPS_MS", "HAPSIM_FAKE_HD_TEMPERATURE"}) {
      unsetenv(name);
    }
    log_ = ::testing::TempDir() + "fake_hd_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv";
    setenv("HAPSIM_FAKE_HD_LOG", log_.c_str(), 1);
    config_.library = HAPSIM_FAKE_HD_PATH;
    config_.calibration_wait_s = 0.2;
    // The tests that check every frame's force are not about stalls: a
    // virtual host's own gaps (12 ms seen on one CI machine) past the 10 ms
    // default would fade their force. The stall test sets its own timeout.
    config_.stall_timeout_s = 1.0;
  }

  // The fake writes its log when the device is disabled (the device's end);
  // device k > 1 of several to log_ + ".k".
  std::vector<FakeFrame> Frames(const std::string& suffix = "") const {
    std::ifstream in(log_ + suffix);
    std::string line;
    std::getline(in, line);  // header
    std::vector<FakeFrame> frames;
    while (std::getline(in, line)) {
      FakeFrame f{};
      std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &f.t_ms, &f.y_mm, &f.fx, &f.fy, &f.fz);
      frames.push_back(f);
    }
    return frames;
  }

  // Runs the servo for `ticks` scheduler ticks, commanding `force_W_N`.
  void Run(OpenHapticsDevice& device, int ticks, const Eigen::Vector3d& force_W_N) {
    std::atomic<bool> stop{false};
    int n = 0;
    const std::function<bool(double)> tick = [&](double t_s) {
      readings_.push_back(device.Read(t_s));
      device.CommandForce(force_W_N);
      return ++n < ticks;
    };
    device.RunServo(tick, stop);
  }

  std::string Opening() {
    try {
      OpenHapticsDevice device(config_);
    } catch (const DeviceError& e) {
      return e.what();
    }
    return "";
  }

  OpenHapticsConfig config_;
  std::string log_;
  std::vector<DeviceReading> readings_;
};

TEST_F(FakeHdTest, AMissingLibraryIsAnErrorNamingItAndTheFlag) {
  config_.library = "/nonexistent/libHD.so";
  const std::string error = Opening();
  EXPECT_NE(error.find("/nonexistent/libHD.so"), std::string::npos) << error;
  EXPECT_NE(error.find("--hd-library"), std::string::npos) << error;
}

TEST_F(FakeHdTest, ALibraryWithoutTheHdFunctionsIsAnErrorNamingTheFunction) {
  config_.library = "libm.so.6";
  const std::string error = Opening();
  EXPECT_NE(error.find("has no function hdInitDevice"), std::string::npos) << error;
}

TEST_F(FakeHdTest, NoDeviceIsAnErrorWithTheHdCodeAndWhatToCheck) {
  setenv("HAPSIM_FAKE_HD_FAULT", "no_device", 1);
  const std::string error = Opening();
  EXPECT_NE(error.find("HD_COMM_ERROR (0x0302)"), std::string::npos) << error;
  EXPECT_NE(error.find("plugged in"), std::string::npos) << error;
}

TEST_F(FakeHdTest, ACalibrationNeedingTheInkwellIsAnErrorAfterTheWait) {
  setenv("HAPSIM_FAKE_HD_FAULT", "calibration_manual", 1);
  const std::string error = Opening();
  EXPECT_NE(error.find("inkwell"), std::string::npos) << error;
}

TEST_F(FakeHdTest, ACalibrationTheDeviceCanDoItselfIsDoneOnOpen) {
  setenv("HAPSIM_FAKE_HD_FAULT", "calibration_update", 1);
  OpenHapticsDevice device(config_);
  EXPECT_TRUE(device.counters().calibrated_on_open);
}

TEST_F(FakeHdTest, TheDeviceLimitsAreReadInWorldUnitsAndDividedByTheWorkspaceScale) {
  setenv("HAPSIM_FAKE_HD_LIMITS", "3.3,0.88,0.7,0.0025", 1);
  config_.workspace.scale = 2.0;
  OpenHapticsDevice device(config_);
  const DeviceLimits limits = device.Limits();
  EXPECT_DOUBLE_EQ(limits.max_force_N, 3.3);
  EXPECT_DOUBLE_EQ(limits.max_continuous_force_N, 0.88);
  EXPECT_DOUBLE_EQ(limits.max_stiffness_N_per_m, 700.0 / 2.0);  // 0.7 N/mm; a 2x workspace feels twice as stiff
  EXPECT_DOUBLE_EQ(limits.max_damping_Ns_per_m, 2.5 / 2.0);
  EXPECT_DOUBLE_EQ(limits.max_velocity_m_per_s, 2.0 * 1.2);  // 1200 mm/s; a 2x workspace moves twice as fast
  EXPECT_EQ(device.Name(), "openhaptics:hapsim fake Omni");
}

// A device whose driver stops at 400 mm/s: the chain zeroes the force from
// 0.4 m/s on (its own 0.6 m/s would let the driver fault first).
TEST_F(FakeHdTest, TheDriversVelocityLimitBecomesTheChainsWhenItIsLower) {
  setenv("HAPSIM_FAKE_HD_LIMITS", "3.3,0.88,0.7,0.0025,400", 1);
  OpenHapticsDevice device(config_);
  EXPECT_DOUBLE_EQ(device.Limits().max_velocity_m_per_s, 0.4);
  SafetyConfig quiet;
  quiet.ramp_in_s = 0.0;
  quiet.max_rise_N_per_s = 1e9;
  quiet.passivity_control = false;
  ForceSafety safety(quiet, device.Limits());
  SafetyInput in;
  in.requested_W_N = Eigen::Vector3d(0, 0, 0.5);
  in.model_age_s = 0.001;
  in.velocity_W_m_per_s = Eigen::Vector3d(0, 0.39, 0);
  EXPECT_DOUBLE_EQ(safety.Apply(in).z(), 0.5);
  in.velocity_W_m_per_s = Eigen::Vector3d(0, 0.41, 0);
  EXPECT_EQ(safety.Apply(in).norm(), 0.0);
  EXPECT_EQ(safety.counters().velocity_limited, 1u);
}

// A motor at 0.9 of its temperature limit: from the first reading on, the
// device gets half the force (full up to 0.8, zero at 1.0), and says so.
TEST_F(FakeHdTest, AMotorNearItsTemperatureLimitDeratesTheForce) {
  setenv("HAPSIM_FAKE_HD_TEMPERATURE", "0.9", 1);
  {
    OpenHapticsDevice device(config_);
    Run(device, 50, Eigen::Vector3d(0, 0, 1.0));  // world +z is the device's +y
    EXPECT_DOUBLE_EQ(device.counters().max_motor_temperature, 0.9);
    EXPECT_GE(device.counters().thermal_derated_ticks, 48u);
  }
  const std::vector<FakeFrame> frames = Frames();
  ASSERT_GE(frames.size(), 48u);
  // Frame 0 precedes the first reading; the last is the loop's end (zero).
  for (std::size_t i = 1; i + 1 < frames.size(); ++i) EXPECT_NEAR(frames[i].fy, 0.5, 1e-12) << "frame " << i;
  EXPECT_EQ(frames.back().fy, 0.0);
}

// Two styluses on one runtime (a lab PC with two devices): each opens its
// own handle, runs its own servo loop on the one scheduler, and its force
// reaches only its own motors — every frame of each, its own 0.4 N or -0.3 N.
TEST_F(FakeHdTest, TwoDevicesRunTheirOwnLoopsOnOneScheduler) {
  {
    OpenHapticsDevice first(config_);
    OpenHapticsDevice second(config_);
    std::thread other([&] {
      std::atomic<bool> stop{false};
      int n = 0;
      const std::function<bool(double)> tick = [&](double) {
        second.CommandForce(Eigen::Vector3d(0, 0, -0.3));
        return ++n < 300;
      };
      second.RunServo(tick, stop);
    });
    Run(first, 300, Eigen::Vector3d(0, 0, 0.4));
    other.join();
    EXPECT_TRUE(first.fault().empty() && second.fault().empty()) << first.fault() << second.fault();
    EXPECT_GE(first.counters().ticks, 300u);
    EXPECT_GE(second.counters().ticks, 300u);
  }
  for (const auto& [suffix, expected_N] : {std::pair{"", 0.4}, std::pair{".2", -0.3}}) {
    const std::vector<FakeFrame> frames = Frames(suffix);
    EXPECT_GE(frames.size(), 299u) << "device log" << suffix;
    for (const FakeFrame& f : frames) {  // 0: before the first command and at the loop's end
      EXPECT_TRUE(f.fy == expected_N || f.fy == 0.0) << "device log" << suffix << " at " << f.t_ms << " ms: " << f.fy;
    }
  }
}

TEST(ThermalForceScale, FullToEightTenthsThenLinearToZeroAtTheLimit) {
  EXPECT_EQ(ThermalForceScale(-1.0), 1.0);  // not reported
  EXPECT_EQ(ThermalForceScale(0.8), 1.0);
  EXPECT_NEAR(ThermalForceScale(0.9), 0.5, 1e-12);
  EXPECT_NEAR(ThermalForceScale(0.95), 0.25, 1e-12);
  EXPECT_EQ(ThermalForceScale(1.0), 0.0);
  EXPECT_EQ(ThermalForceScale(1.5), 0.0);
  EXPECT_EQ(ThermalForceScale(std::nan("")), 1.0);
}

// The device frame has y up and z towards the user; ours z up, y away.
TEST_F(FakeHdTest, PosesArriveInMetresInTheWorldFrameAndForcesLeaveInTheDeviceFrame) {
  setenv("HAPSIM_FAKE_HD_SCRIPT", "press", 1);
  config_.workspace.offset_W_m = Eigen::Vector3d(0.1, 0.0, 0.0);
  {
    OpenHapticsDevice device(config_);
    Run(device, 300, Eigen::Vector3d(0.1, 0.2, 0.3));
    EXPECT_EQ(device.counters().ticks, 300u);
  }
  const auto frames = Frames();
  ASSERT_EQ(frames.size(), 300u);  // one frame per servo tick
  ASSERT_EQ(readings_.size(), 300u);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    // Read before the frame's force: the pose of the same frame [mm -> m].
    EXPECT_NEAR(readings_[i].tip_W_m.z(), frames[i].y_mm * 1e-3, 1e-12) << i;
    EXPECT_DOUBLE_EQ(readings_[i].tip_W_m.x(), 0.1);
    EXPECT_DOUBLE_EQ(readings_[i].tip_W_m.y(), 0.0);
    // F_D = R_WD^T F_W: x_D = x_W, y_D = z_W, z_D = -y_W; the last frame ends the loop at zero.
    const bool last = i + 1 == frames.size();
    EXPECT_DOUBLE_EQ(frames[i].fx, last ? 0.0 : 0.1) << i;
    EXPECT_DOUBLE_EQ(frames[i].fy, last ? 0.0 : 0.3) << i;
    EXPECT_DOUBLE_EQ(frames[i].fz, last ? 0.0 : -0.2) << i;
  }
  // Descending at 10 mm/s: velocity in world -z [m/s].
  EXPECT_NEAR(readings_[100].velocity_W_m_per_s.z(), -0.010, 1e-12);
}

TEST_F(FakeHdTest, AForceFaultEndsTheLoopWithZeroForceAndSaysWhy) {
  setenv("HAPSIM_FAKE_HD_FAULT", "force_fault:150", 1);
  std::string fault;
  {
    OpenHapticsDevice device(config_);
    Run(device, 100000, Eigen::Vector3d(0, 0, 1.0));  // never stops by itself: only the fault ends it
    fault = device.fault();
  }
  EXPECT_NE(fault.find("HD_FORCE_ERROR (0x0204)"), std::string::npos) << fault;
  const auto frames = Frames();
  ASSERT_GE(frames.size(), 2u);
  // The frame that reported the fault is followed by one at exactly zero, and nothing after it.
  EXPECT_EQ(frames.back().fx, 0.0);
  EXPECT_EQ(frames.back().fy, 0.0);
  EXPECT_EQ(frames.back().fz, 0.0);
  EXPECT_GE(frames[frames.size() - 2].t_ms, 150.0);
  EXPECT_LT(frames.back().t_ms - 150.0, 2.0);  // within one servo period of the fault (1 ms frames)
}

TEST_F(FakeHdTest, AStalledSchedulerIsCountedAndTheForceResumesFromZero) {
  setenv("HAPSIM_FAKE_HD_FAULT", "stall:100:40", 1);
  config_.resume_ramp_s = 0.5;
  config_.stall_timeout_s = 0.025;  // the injected 40 ms, not a busy CI machine's odd late tick
  OpenHapticsCounters counters;
  {
    OpenHapticsDevice device(config_);
    Run(device, 400, Eigen::Vector3d(0, 0, 1.0));
    counters = device.counters();
  }
  EXPECT_GE(counters.stalls, 1u);  // the injected one (a loaded machine may add its own)
  EXPECT_GE(counters.longest_gap_s, 0.040);
  const auto frames = Frames();
  std::size_t resumed = 0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    if (frames[i].t_ms - frames[i - 1].t_ms > 30.0) resumed = i;
  }
  ASSERT_GT(resumed, 0u);
  EXPECT_EQ(frames[resumed].fy, 0.0);       // the first frame after the stall: zero
  EXPECT_GT(frames[resumed - 1].fy, 0.99);  // before it: the full 1 N (F_D y = F_W z)
  // Then back over 0.5 s of wall time, never in a step: 100 frames later about 100 ms / 500 ms of
  // the force (0.2 N at an exact 1 kHz; the bounds allow a loaded machine's late ticks).
  ASSERT_GT(frames.size(), resumed + 100);
  EXPECT_GT(frames[resumed + 100].fy, 0.15);
  EXPECT_LT(frames[resumed + 100].fy, 0.35);
  for (std::size_t i = resumed + 1; i < resumed + 100; ++i) EXPECT_GE(frames[i].fy, frames[i - 1].fy) << i;
}

TEST_F(FakeHdTest, MotorTemperatureIsReadWhenTheDeviceReportsIt) {
  {
    OpenHapticsDevice device(config_);
    Run(device, 10, Eigen::Vector3d::Zero());
    EXPECT_DOUBLE_EQ(device.counters().max_motor_temperature, 0.25);
  }
  setenv("HAPSIM_FAKE_HD_FAULT", "no_temperature", 1);
  OpenHapticsDevice device(config_);
  Run(device, 10, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(device.counters().max_motor_temperature, -1.0);
  EXPECT_TRUE(device.fault().empty());  // a missing temperature is not a fault
}

TEST(OpenHapticsConfig, BadWorkspaceAndTimingsAreNamed) {
  OpenHapticsConfig c;
  c.workspace.scale = 0.0;
  EXPECT_THROW(ValidateOpenHapticsConfig(c), std::invalid_argument);
  c = {};
  c.stall_timeout_s = 0.0;
  EXPECT_THROW(ValidateOpenHapticsConfig(c), std::invalid_argument);
  c = {};
  c.library.clear();
  EXPECT_THROW(ValidateOpenHapticsConfig(c), std::invalid_argument);
}

}  // namespace
}  // namespace hapsim::bridge
