#include "hapsim/viewer/frame_log.h"

#include <algorithm>
#include <array>

namespace hapsim::viewer {

namespace {
constexpr char kMagic[8] = {'H', 'S', 'F', 'R', 'A', 'M', 'E', '1'};
constexpr std::uint32_t kMaxFrameBytes = 64u << 20;
}  // namespace

bool FrameLogWriter::Open(const std::string& path, std::string* error) {
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) {
    *error = "cannot write " + path;
    return false;
  }
  out_.write(kMagic, sizeof kMagic);
  return static_cast<bool>(out_);
}

bool FrameLogWriter::Write(const hapsim::v1::Frame& frame) {
  buffer_.clear();
  frame.SerializeToString(&buffer_);
  const auto n = static_cast<std::uint32_t>(buffer_.size());
  const std::array<char, 4> length = {static_cast<char>(n & 0xff), static_cast<char>((n >> 8) & 0xff),
                                      static_cast<char>((n >> 16) & 0xff), static_cast<char>((n >> 24) & 0xff)};
  out_.write(length.data(), 4);
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  out_.flush();  // a killed viewer leaves a readable recording up to its last frame
  ++frames_;
  return static_cast<bool>(out_);
}

bool ReadFrameLog(const std::string& path, std::vector<hapsim::v1::Frame>* frames, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = "cannot read " + path;
    return false;
  }
  char magic[sizeof kMagic] = {};
  if (!in.read(magic, sizeof magic) || !std::equal(magic, magic + sizeof magic, kMagic)) {
    *error = path + " is not a hapsim frame recording (no HSFRAME1 header)";
    return false;
  }
  frames->clear();
  std::string buffer;
  while (true) {
    unsigned char length[4];
    if (!in.read(reinterpret_cast<char*>(length), 4)) {
      if (in.gcount() == 0) return true;
      *error = path + ": truncated after frame " + std::to_string(frames->size());
      return false;
    }
    const std::uint32_t n = length[0] | (length[1] << 8) | (length[2] << 16) | (static_cast<std::uint32_t>(length[3]) << 24);
    if (n > kMaxFrameBytes) {
      *error = path + ": frame " + std::to_string(frames->size()) + " claims " + std::to_string(n) + " bytes (max 64 MiB)";
      return false;
    }
    buffer.resize(n);
    if (!in.read(buffer.data(), n)) {
      *error = path + ": frame " + std::to_string(frames->size()) + " is truncated";
      return false;
    }
    hapsim::v1::Frame frame;
    if (!frame.ParseFromString(buffer)) {
      *error = path + ": frame " + std::to_string(frames->size()) + " does not parse";
      return false;
    }
    frames->push_back(std::move(frame));
  }
}

}  // namespace hapsim::viewer
