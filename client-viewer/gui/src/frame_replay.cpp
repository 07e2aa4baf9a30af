#include "hapsim/gui/frame_replay.h"

#include <spdlog/spdlog.h>

#include "hapsim/viewer/frame_log.h"

namespace hapsim::gui {

bool FrameReplay::Load(const std::string& path, std::string* error) {
  return viewer::ReadFrameLog(path, &frames_, error);
}

bool FrameReplay::Advance(double elapsed_s, LiveScene* scene) {
  while (next_ < frames_.size()) {
    const hapsim::v1::Frame& wire = frames_[next_];
    if (next_ > 0 && wire.sim_time_s() - frames_.front().sim_time_s() > elapsed_s) break;
    const viewer::ViewerFrame& frame = decoder_.Decode(wire);
    std::string why;
    const auto result = decoder_.ApplyMesh(wire, &why);
    if (result != viewer::ApplyResult::kApplied) {
      spdlog::warn("recorded frame {} refused ({}): {}", next_, viewer::ToString(result), why);
    } else {
      scene->OnFrame(frame, decoder_.mesh());
    }
    ++next_;
  }
  return next_ < frames_.size();
}

std::optional<viewer::CompactMesh> FrameReplay::Mesh() const {
  return decoder_.mesh().has_mesh() ? std::optional(decoder_.mesh().Compact()) : std::nullopt;
}

}  // namespace hapsim::gui
