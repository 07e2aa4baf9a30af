// The model-jump transition, through the servo channel (the stylus held 2 mm
// into a 500 N/m contact, every other stage quiet): a model whose force at
// the stylus jumps is blended in over 10 ticks, no tick changing the force
// by more than 0.07 |F| + 0.01 N (checked to 1e-12 N), and then renders
// exactly the new model's force.
#include "hapsim/servo/model_transition.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "hapsim/common/clock.h"
#include "hapsim/servo/servo_channel.h"
#include "safety_test_setup.h"

// Its own namespace: the test files are compiled in batches (unity build).
namespace hapsim::bridge::model_transition_test {
namespace {

constexpr double kBoundTolN = 1e-12;

double StepBoundN(double previous_N) { return 0.07 * previous_N + 0.01; }

// Contact at the surface z = anchor_z: 500 N/m x (anchor_z + 2 mm) at the stylus.
ReceivedModel ContactAt(double anchor_z_m) {
  ReceivedModel m;
  m.model.state = core::ContactState::kContact;
  m.model.anchor_W_m = Eigen::Vector3d(0, 0, anchor_z_m);
  m.model.stiffness_N_per_m = 500.0;
  return m;
}

class ModelJump : public ::testing::Test {
 protected:
  ModelJump() {
    device_.reading.tip_W_m = Eigen::Vector3d(0, 0, -0.002);
    SafetyConfig c = test::QuietChain();
    c.model_transition_ticks = SafetyConfig{}.model_transition_ticks;
    ChannelConfig config;
    config.safety = c;
    channel_ = std::make_unique<ServoChannel>(&device_, config);
  }
  // One tick, with a new model if given; returns the force commanded.
  double Tick(const ReceivedModel* model = nullptr) {
    channel_->Sense(0.0);
    if (model != nullptr) {
      ReceivedModel m = *model;
      m.echo_pose_seq = channel_->pose().seq;
      m.received_ns = common::SteadyNowNs();
      inbox_.Publish(m);
    } else {
      // Keep the held model fresh for the watchdog: republish it unchanged.
      ReceivedModel m = held_;
      m.echo_pose_seq = channel_->pose().seq;
      m.received_ns = common::SteadyNowNs();
      inbox_.Publish(m);
    }
    if (model != nullptr) held_ = *model;
    return channel_->Actuate(inbox_).force_W_N.z();
  }

  test::StillDevice device_;
  common::LatestValue<ReceivedModel> inbox_;
  std::unique_ptr<ServoChannel> channel_;
  ReceivedModel held_;
};

// 1 N -> 1.5 N: the blend's 0.05 N per tick is under the bound (>= 0.08 N),
// so the force is 1 + 0.05 k on the k-th tick and exactly 1.5 N from tick 10.
TEST_F(ModelJump, ASmallJumpIsBlendedLinearlyOverTenTicks) {
  const ReceivedModel a = ContactAt(0.0), b = ContactAt(0.001);
  for (int n = 0; n < 5; ++n) ASSERT_NEAR(Tick(n == 0 ? &a : nullptr), 1.0, 1e-12);
  double previous_N = 1.0;
  for (int k = 1; k <= 12; ++k) {
    const double f_N = Tick(k == 1 ? &b : nullptr);
    ASSERT_NEAR(f_N, k <= 10 ? 1.0 + 0.05 * k : 1.5, 1e-12) << "tick " << k;
    ASSERT_LE(std::abs(f_N - previous_N), StepBoundN(previous_N) + kBoundTolN) << "tick " << k;
    previous_N = f_N;
  }
  EXPECT_EQ(channel_->last_tick().requested_W_N.z(), channel_->last_tick().force_W_N.z());
  EXPECT_EQ(channel_->safety_counters().model_jumps, 1u);
  EXPECT_EQ(channel_->safety_counters().jump_steps_limited, 0u);
}

// A contact that jumps from 0.05 N (anchor 1.9 mm below) to 2 N (2 mm
// above): every tick the bound holds the step (F_k = 1.07 F_{k-1} + 0.01),
// so the force reaches 2 N on the first tick k with
// 1.07^k (0.05 + 1/7) >= 2 + 1/7, k = 36, and stays there.
TEST_F(ModelJump, ALargeJumpRisesByTheJustNoticeableStepUntilItArrives) {
  const ReceivedModel a = ContactAt(-0.0019), b = ContactAt(0.002);
  ASSERT_NEAR(Tick(&a), 0.05, 1e-12);
  const int arrival = static_cast<int>(std::ceil(std::log((2.0 + 1.0 / 7) / (0.05 + 1.0 / 7)) / std::log(1.07)));
  ASSERT_EQ(arrival, 36);
  double previous_N = 0.05;
  for (int k = 1; k <= 40; ++k) {
    const double f_N = Tick(k == 1 ? &b : nullptr);
    const double bound_N = StepBoundN(previous_N);
    ASSERT_LE(std::abs(f_N - previous_N), bound_N + kBoundTolN) << "tick " << k;
    if (k < arrival) {
      ASSERT_NEAR(f_N - previous_N, bound_N, kBoundTolN) << "tick " << k;  // held to the bound
    } else {
      ASSERT_NEAR(f_N, 2.0, 1e-12) << "tick " << k;
    }
    previous_N = f_N;
  }
  EXPECT_EQ(channel_->safety_counters().model_jumps, 1u);
  EXPECT_EQ(channel_->safety_counters().jump_steps_limited, static_cast<std::uint64_t>(arrival));
}

// A model whose force at the stylus is within one step (1.0 -> 1.05 N) is
// not a jump: taken at once.
TEST_F(ModelJump, AChangeWithinOneStepIsTakenAtOnce) {
  const ReceivedModel a = ContactAt(0.0), b = ContactAt(0.0001);
  Tick(&a);
  EXPECT_NEAR(Tick(&b), 1.05, 1e-12);
  EXPECT_EQ(channel_->safety_counters().model_jumps, 0u);
}

// A third model arriving mid-transition (1 -> 2 N, then after 3 ticks back
// to 0.5 N): the force never steps by more than the bound and ends at 0.5 N.
TEST_F(ModelJump, AJumpDuringATransitionStaysContinuous) {
  const ReceivedModel a = ContactAt(0.0), b = ContactAt(0.002), c = ContactAt(-0.001);
  double previous_N = Tick(&a);
  for (int k = 1; k <= 40; ++k) {
    const double f_N = Tick(k == 1 ? &b : k == 4 ? &c : nullptr);
    ASSERT_LE(std::abs(f_N - previous_N), StepBoundN(previous_N) + kBoundTolN) << "tick " << k;
    previous_N = f_N;
  }
  EXPECT_NEAR(previous_N, 0.5, 1e-12);
  EXPECT_EQ(channel_->safety_counters().model_jumps, 2u);
}

TEST(ModelTransition, TurnedOffAJumpPassesAtOnce) {
  ModelTransition t(TransitionConfig{0, 0.07, 0.01});
  core::LocalForceModel free;
  const Eigen::Vector3d x = Eigen::Vector3d::Zero();
  EXPECT_FALSE(t.Offer(free, Eigen::Vector3d(0, 0, 2.0), x, x));
  bool held_back = true;
  EXPECT_EQ(t.Step(Eigen::Vector3d(0, 0, 2.0), x, x, &held_back).z(), 2.0);
  EXPECT_FALSE(held_back);
}

// Garbage in the new model is not blended: the NaN passes on (the chain
// zeroes and counts it) and the transition ends.
TEST(ModelTransition, ANonFiniteForceEndsTheTransition) {
  ModelTransition t(TransitionConfig{});
  core::LocalForceModel free;
  const Eigen::Vector3d x = Eigen::Vector3d::Zero();
  ASSERT_TRUE(t.Offer(free, Eigen::Vector3d(0, 0, 2.0), x, x));
  bool held_back = false;
  EXPECT_FALSE(t.Step(Eigen::Vector3d(0, 0, std::nan("")), x, x, &held_back).allFinite());
  EXPECT_FALSE(t.active());
  EXPECT_EQ(t.Step(Eigen::Vector3d(0, 0, 2.0), x, x, &held_back).z(), 2.0);
}

}  // namespace
}  // namespace hapsim::bridge::model_transition_test
