#include "hapsim/servo/servo_channel.h"

#include <algorithm>
#include <limits>
#include <string_view>

#include "hapsim/common/clock.h"

namespace hapsim::bridge {

ServoChannel::ServoChannel(HapticDevice* device, const ChannelConfig& config)
    : device_(device),
      period_s_(config.period_s),
      safety_(config.safety, device->Limits()),
      warn_age_ns_(static_cast<std::int64_t>(config.safety.warn_age_s * 1e9)),
      pose_deadband_(config.pose_deadband),
      physics_reference_(config.physics_reference),
      delay_(config.model_delay_s),
      round_trip_s_(config.stats_window),
      model_age_s_(config.stats_window),
      physics_age_s_(config.stats_window) {
  pose_.device_id = config.device_id;
  sent_seq_.fill(~0ull);
}

const DeviceReading& ServoChannel::Sense(double t_s) { return Sense(t_s, common::SteadyNowNs()); }

const DeviceReading& ServoChannel::Sense(double t_s, std::int64_t now_ns) {
  tick_.reading = device_->Read(t_s);
  const DeviceReading& r = tick_.reading;
  sensed_ns_ = now_ns;
  const std::uint64_t seq = next_seq_++;
  pose_.seq = seq;
  pose_.t_device_ns = sensed_ns_;
  pose_.tool.valid = true;
  pose_.tool.tip_W_m = r.tip_W_m;
  pose_.tool.orientation_W = r.orientation_W;
  pose_.tool.velocity_W_m_per_s = r.velocity_W_m_per_s;
  pose_.tool.buttons = r.buttons;
  sent_seq_[seq % kSentRing] = seq;
  sent_ns_[seq % kSentRing] = sensed_ns_;
  sent_tip_W_m_[seq % kSentRing] = r.tip_W_m;
  sent_velocity_W_m_per_s_[seq % kSentRing] = r.velocity_W_m_per_s;
  pose_due_ = pose_deadband_.Offer(pose_);
  if (pose_due_) ++counters_.poses_due;
  return r;
}

bool ServoChannel::TakeNewestModel(common::LatestValue<ReceivedModel>& inbox) {
  tick_.round_trip_s = -1.0;
  ReceivedModel incoming;
  if (!(delay_.enabled() ? delay_.Take(inbox, sensed_ns_, &incoming) : inbox.TakeIfNew(&incoming))) return false;
  const std::uint64_t echo = incoming.echo_pose_seq;
  // A model computed from an older pose than the held one was overtaken in
  // transit: it describes where the tool was, so it is discarded. Only while
  // the held model is fresh — if the stream stalled (held model older than
  // the watchdog's warning age), whatever arrives is newer than what we hold;
  // so is anything after a held model answering no pose of ours (another run's).
  const bool held_is_fresh = have_model_ && physics_known_ && sensed_ns_ - model_.received_ns <= warn_age_ns_;
  if (held_is_fresh && echo < counters_.last_echo_seq) {
    ++counters_.echo_regressions;
    return false;
  }
  const std::size_t echo_slot = echo % kSentRing;
  const bool first_answer = counters_.models_taken == 0 || echo != counters_.last_echo_seq;
  const bool echo_known = sent_seq_[echo_slot] == echo;  // a pose this channel sensed (within the ring)
  const bool echo_remembered = first_answer && echo_known;
  if (echo_remembered && physics_reference_) {
    tick_.physics_at_echo_W_N =
        core::EvaluateLocalForce(incoming.model, sent_tip_W_m_[echo_slot], sent_velocity_W_m_per_s_[echo_slot]);
  }
  // Unpacked and checked by the receive thread (hapsim::wire); rendered no
  // stiffer than the device can, and blended in if it jumps.
  safety_.CapModel(&incoming.model);
  const DeviceReading& r = tick_.reading;
  // Evaluated once: the transition compares it with the old model, and it is this tick's request.
  tick_.requested_W_N = core::EvaluateLocalForce(incoming.model, r.tip_W_m, r.velocity_W_m_per_s);
  if (have_model_) safety_.OfferModel(model_.model, tick_.requested_W_N, r.tip_W_m, r.velocity_W_m_per_s);
  if (have_model_ && incoming.server_instance == model_.server_instance && incoming.seq > model_.seq + 1)
    counters_.models_unused += incoming.seq - model_.seq - 1;
  model_ = incoming;
  promised_gap_s_ = std::min(model_.next_model_within_s, kLongestPromisedGapS);
  // Later models for the same pose answer it too: their physics is of the
  // stylus as long after that pose as the server held (extrapolated) it.
  physics_known_ = echo_known;
  if (physics_known_) physics_sensed_ns_ = sent_ns_[echo_slot] + model_.echo_pose_held_ns;
  if (counters_.models_taken == 0) counters_.first_echo_seq = echo;
  counters_.last_echo_seq = echo;
  ++counters_.models_taken;
  if (echo_remembered) {
    tick_.round_trip_s = static_cast<double>(model_.received_ns - physics_sensed_ns_) * 1e-9;
    round_trip_s_.Record(tick_.round_trip_s);
  }
  have_model_ = true;
  return true;
}

const ChannelTick& ServoChannel::Actuate(common::LatestValue<ReceivedModel>& inbox) {
  const bool took_model = TakeNewestModel(inbox);  // evaluates the new model at the stylus
  tick_.took_model = took_model;
  // A model can land between Sense's clock read and the take: age 0, not
  // negative (negative means "no model" to the safety layer).
  tick_.model_age_s =
      have_model_ ? std::max(0.0, static_cast<double>(sensed_ns_ - model_.received_ns) * 1e-9) : -1.0;
  if (have_model_) model_age_s_.Record(tick_.model_age_s);
  // Within the gap the server promised (its deadband's keep-alive), a held
  // model is one the server still finds right for where the tool is: the
  // stream is not late, and its physics is as old as when it arrived.
  tick_.model_overdue_s = -1.0;
  tick_.physics_age_s = -1.0;
  if (have_model_) {
    tick_.model_overdue_s = std::max(0.0, tick_.model_age_s - promised_gap_s_);
    tick_.physics_age_s =
        physics_known_
            ? std::max(0.0, static_cast<double>(model_.received_ns - physics_sensed_ns_) * 1e-9) + tick_.model_overdue_s
            : std::numeric_limits<double>::infinity();
    if (physics_known_) physics_age_s_.Record(tick_.physics_age_s);
  }

  const DeviceReading& r = tick_.reading;
  if (!took_model) {
    tick_.requested_W_N = have_model_ ? core::EvaluateLocalForce(model_.model, r.tip_W_m, r.velocity_W_m_per_s)
                                      : Eigen::Vector3d::Zero();
  }
  tick_.blended_W_N = safety_.Blend(tick_.requested_W_N, r.tip_W_m, r.velocity_W_m_per_s);
  SafetyInput in;
  in.requested_W_N = tick_.blended_W_N;
  in.velocity_W_m_per_s = r.velocity_W_m_per_s;
  in.buttons = r.buttons;
  in.model_age_s = tick_.model_age_s;
  in.model_gap_allowance_s = promised_gap_s_;
  in.physics_age_s = tick_.physics_age_s;
  in.dt_s = period_s_;
  tick_.force_W_N = safety_.Apply(in);
  device_->CommandForce(tick_.force_W_N);
  RecordPeaks();
  ++counters_.ticks;
  return tick_;
}

void ServoChannel::RecordPeaks() {
  const double magnitude = tick_.force_W_N.norm();
  counters_.peak_force_N = std::max(counters_.peak_force_N, magnitude);
  const std::string_view phase = tick_.reading.phase;
  if (phase == "press" || phase == "hold") {
    counters_.peak_force_pressing_N = std::max(counters_.peak_force_pressing_N, magnitude);
  }
  if (phase == "withdraw" && tick_.reading.tip_W_m.z() > 0.001) {
    counters_.peak_force_withdrawn_N = std::max(counters_.peak_force_withdrawn_N, magnitude);
  }
}

}  // namespace hapsim::bridge
