// A recording of a viewer's frame stream, for replaying a session into the
// viewer without a server (golden pictures, benchmarks, bug reports).
// Format: the 8 bytes "HSFRAME1", then per frame a 4-byte little-endian
// length and the serialised hapsim.v1.Frame. A frame is at most 64 MiB.
#pragma once
#include <cstdint>
#include <fstream>
#include <istream>
#include <string>
#include <vector>

#include "hapsim/v1/viewer.pb.h"

namespace hapsim::viewer {

class FrameLogWriter {
 public:
  bool Open(const std::string& path, std::string* error);
  bool Write(const hapsim::v1::Frame& frame);  // false when the disk write failed
  std::uint64_t frames() const { return frames_; }

 private:
  std::ofstream out_;
  std::string buffer_;
  std::uint64_t frames_ = 0;
};

// Reads every frame of a recording. False with *error naming the file and
// the frame when it is not a recording, truncated or holds a bad frame.
bool ReadFrameLog(const std::string& path, std::vector<hapsim::v1::Frame>* frames, std::string* error);
// The same from a stream; `name` names it in errors.
bool ReadFrameLog(std::istream& in, const std::string& name, std::vector<hapsim::v1::Frame>* frames,
                  std::string* error);

}  // namespace hapsim::viewer
