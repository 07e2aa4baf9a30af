// Plays a recording (viewer::FrameLogWriter) into a LiveScene at the pace of
// its sim time, or all at once for a still picture, decoding each frame like
// a live stream does.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "hapsim/gui/live_scene.h"
#include "hapsim/v1/viewer.pb.h"
#include "hapsim/viewer/frame_decoder.h"

namespace hapsim::gui {

class FrameReplay {
 public:
  bool Load(const std::string& path, std::string* error);
  std::size_t size() const { return frames_.size(); }
  // Plays every frame due by `elapsed_s` after the first one; false at the end.
  bool Advance(double elapsed_s, LiveScene* scene);
  void PlayAll(LiveScene* scene) { Advance(1e300, scene); }
  // The mesh the frames played so far lead to, nothing before a keyframe.
  std::optional<viewer::CompactMesh> Mesh() const;

 private:
  std::vector<hapsim::v1::Frame> frames_;
  std::size_t next_ = 0;
  viewer::FrameDecoder decoder_;
};

}  // namespace hapsim::gui
