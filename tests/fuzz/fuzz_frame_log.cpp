// Any bytes as a viewer recording (hapsim-viewer --replay FILE; the format of
// client-viewer/include/hapsim/viewer/frame_log.h). Invariants: the reader
// either returns every frame, and then writing those frames again gives a
// recording that reads back to the same frames, or refuses with a message
// that names the file; it never allocates beyond what the input holds (a
// claimed length past the end is "truncated", checked by -malloc_limit_mb).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include "fuzz_setup.h"

#include "hapsim/viewer/frame_log.h"

namespace {

using namespace hapsim;

// A real recording of three frames (a keyframe and two deltas), made by the
// writer, and two damaged ones.
void WriteSeeds(const std::string& dir) {
  v1::Frame key;
  key.set_seq(0);
  auto* k = key.mutable_keyframe();
  k->set_quantum_m(1e-5);
  for (int v : {0, 0, 0, 100, 0, 0, 0, 100, 0}) k->add_positions_q(v);
  for (int v : {0, 1, 2}) k->add_triangles(static_cast<std::uint32_t>(v));
  k->add_triangle_parts(0);
  k->add_part_names("skin");
  k->set_vertex_capacity(4);
  k->set_triangle_capacity(2);
  v1::Frame delta;
  delta.set_seq(1);
  delta.mutable_delta()->add_index_gaps(1);
  for (int v : {0, 0, -3}) delta.mutable_delta()->add_position_dq(v);
  const std::string path = dir + "/three_frames";
  viewer::FrameLogWriter writer;
  std::string error;
  if (!writer.Open(path, &error) || !writer.Write(key) || !writer.Write(delta)) std::exit(1);
  delta.set_seq(2);
  if (!writer.Write(delta)) std::exit(1);
  std::ofstream(dir + "/header_only", std::ios::binary) << "HSFRAME1";
  std::ofstream(dir + "/huge_claim", std::ios::binary) << std::string("HSFRAME1\xff\xff\xff\x03", 12);
}

std::string DeterministicBytes(const v1::Frame& frame) {
  std::string bytes;
  google::protobuf::io::StringOutputStream stream(&bytes);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  frame.SerializeToCodedStream(&coded);
  coded.Trim();
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapsim::fuzz::SetUpServiceFuzzer(&WriteSeeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<v1::Frame> frames;
  std::string error;
  if (!viewer::ReadFrameLog(in, "input", &frames, &error)) {
    if (error.rfind("input", 0) != 0) std::abort();  // the message names the file
    return 0;
  }
  // Written again and read back: the same frames.
  std::ostringstream again;
  again.write("HSFRAME1", 8);
  for (const auto& f : frames) {
    const std::string bytes = f.SerializeAsString();
    const auto n = static_cast<std::uint32_t>(bytes.size());
    const char length[4] = {static_cast<char>(n & 0xff), static_cast<char>((n >> 8) & 0xff),
                            static_cast<char>((n >> 16) & 0xff), static_cast<char>((n >> 24) & 0xff)};
    again.write(length, 4);
    again << bytes;
  }
  std::istringstream back(again.str());
  std::vector<v1::Frame> reread;
  if (!viewer::ReadFrameLog(back, "again", &reread, &error) || reread.size() != frames.size()) std::abort();
  // Compared as bytes, not field by field: a NaN double (any bytes can hold
  // one) is unequal to itself, yet it must survive the round trip bit for bit.
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (DeterministicBytes(frames[i]) != DeterministicBytes(reread[i])) std::abort();
  return 0;
}
