#include "hapsim/service/frame_pump.h"

#include <chrono>

#include "hapsim/runtime/clock.h"
#include "hapsim/service/viewer_link.h"

namespace hapsim::service {

FramePump::FramePump(SessionRegistry* registry, double poll_period_s)
    : registry_(registry), poll_period_s_(poll_period_s) {}

FramePump::~FramePump() { Stop(); }

void FramePump::Start() {
  stop_ = false;
  thread_ = std::thread([this] {
    const auto period = std::chrono::duration<double>(poll_period_s_);
    while (!stop_.load()) {
      PumpOnce();
      std::this_thread::sleep_for(period);
    }
  });
}

void FramePump::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void FramePump::PumpOnce() {
  const std::int64_t now = runtime::SteadyNowNs();
  const auto table = registry_->Table();  // never the registry mutex a slow Create may hold
  for (const auto& [id, session] : *table) {
    std::shared_ptr<const SceneSnapshot> fresh;
    if (session->TakeSnapshot(&fresh)) session->SetLatestSnapshot(fresh);
    const auto latest = session->LatestSnapshot();
    if (!latest) continue;
    for (const auto& viewer : session->Viewers()) viewer->Offer(latest, now);
  }
}

}  // namespace hapsim::service
