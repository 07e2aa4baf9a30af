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
  return ReadFrameLog(in, path, frames, error);
}

namespace {

enum class FrameRead { kFrame, kEnd, kBad };

// Frame number `index` of the recording `name`, length-prefixed.
// `left_bytes` (-1: unknown) bounds any claimed length: a damaged header
// cannot make the reader allocate 64 MiB for a frame that is not there.
FrameRead ReadOneFrame(std::istream& in, const std::string& name, std::size_t index, std::streamoff left_bytes,
                       std::string* buffer, hapsim::v1::Frame* frame, std::string* error) {
  auto which = [&] { return name + ": frame " + std::to_string(index); };
  unsigned char length[4];
  if (!in.read(reinterpret_cast<char*>(length), 4)) {
    if (in.gcount() == 0) return FrameRead::kEnd;
    *error = name + ": truncated after frame " + std::to_string(index);
    return FrameRead::kBad;
  }
  const std::uint32_t n =
      length[0] | (length[1] << 8) | (length[2] << 16) | (static_cast<std::uint32_t>(length[3]) << 24);
  if (n > kMaxFrameBytes) {
    *error = which() + " claims " + std::to_string(n) + " bytes (max 64 MiB)";
    return FrameRead::kBad;
  }
  const bool past_the_end = left_bytes >= 0 && static_cast<std::streamoff>(n) > left_bytes - 4;
  if (!past_the_end) buffer->resize(n);
  if (past_the_end || !in.read(buffer->data(), n)) {
    *error = which() + " is truncated";
    return FrameRead::kBad;
  }
  if (!frame->ParseFromString(*buffer)) {
    *error = which() + " does not parse";
    return FrameRead::kBad;
  }
  return FrameRead::kFrame;
}

}  // namespace

bool ReadFrameLog(std::istream& in, const std::string& name, std::vector<hapsim::v1::Frame>* frames,
                  std::string* error) {
  const std::istream::pos_type start = in.tellg();
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  in.seekg(start);
  const bool sized = start != std::istream::pos_type(-1) && end != std::istream::pos_type(-1);
  char magic[sizeof kMagic] = {};
  if (!in.read(magic, sizeof magic) || !std::equal(magic, magic + sizeof magic, kMagic)) {
    *error = name + " is not a hapsim frame recording (no HSFRAME1 header)";
    return false;
  }
  frames->clear();
  std::string buffer;
  while (true) {
    const std::streamoff left = sized ? static_cast<std::streamoff>(end - in.tellg()) : -1;
    hapsim::v1::Frame frame;
    switch (ReadOneFrame(in, name, frames->size(), left, &buffer, &frame, error)) {
      case FrameRead::kEnd:
        return true;
      case FrameRead::kBad:
        return false;
      case FrameRead::kFrame:
        frames->push_back(std::move(frame));
        break;
    }
  }
}

}  // namespace hapsim::viewer
