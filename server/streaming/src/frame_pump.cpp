#include "hapsim/streaming/frame_pump.h"

#include <chrono>

#include "hapsim/common/clock.h"
#include "hapsim/common/thread_setup.h"

namespace hapsim::service {

FramePump::FramePump(const SessionRegistry* registry, ViewerHub* hub, PassListener after_pass, double poll_period_s,
                     double idle_poll_period_s)
    : registry_(registry),
      hub_(hub),
      after_pass_(std::move(after_pass)),
      poll_period_s_(poll_period_s),
      idle_poll_period_s_(idle_poll_period_s) {}

FramePump::~FramePump() { Stop(); }

void FramePump::Start() {
  stop_ = false;
  thread_ = std::thread([this] {
    const auto period = std::chrono::duration<double>(poll_period_s_);
    const auto idle_period = std::chrono::duration<double>(idle_poll_period_s_);
    while (!stop_.load()) {
      PumpOnce();
      std::this_thread::sleep_for(hub_->AnyViewers() ? period : idle_period);
    }
  });
  common::NameThread(thread_, "frame-pump");  // told apart from the tick path in per-thread CPU figures
}

void FramePump::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void FramePump::PumpOnce() {
  // The copy-on-write table: never the registry mutex a slow Create may hold.
  const auto table = registry_->Table();
  hub_->Pump(*table, common::SteadyNowNs());
  if (after_pass_) after_pass_(*table);
}

}  // namespace hapsim::service
