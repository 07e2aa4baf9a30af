// Any bytes as a viewer's frame stream: the input is a sequence of frames,
// each a 2-byte little-endian length and that many bytes of a serialised
// hapsim.v1.Frame (keyframe or delta, with or without topology edits),
// applied after a valid keyframe of a small cut-ready grid. Invariants
// (viewer/mesh_cache.h): a frame the cache refuses changes nothing (same
// vertices, same triangles); after any frame the cache's mesh is sound
// (every triangle names three distinct live vertices, positions finite).
//
// HAPSIM_FUZZ_WRITE_SEEDS=DIR: write seed inputs made by the real encoder
// (keyframe, deltas, topology edits of a cut) into DIR and exit.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "grid_session.h"
#include "hapsim/streaming/frame_encoder.h"
#include "hapsim/viewer/mesh_cache.h"

namespace {

using namespace hapsim;

// A 6 x 6 grid with room for a cut's edits, and the server side of a stream.
struct Server : fuzz::GridSession {
  service::StreamEncoderState encoder;
  std::string NextFrame() {
    const auto s = Publish();
    history.Absorb(*s);
    v1::Frame f;
    service::EncodeFrame(*s, history, &encoder, &f);
    return f.SerializeAsString();
  }
};

std::string& BaseKeyframe() {
  static std::string key = Server().NextFrame();
  return key;
}

void Append(std::string* input, const std::string& frame) {
  input->push_back(static_cast<char>(frame.size() & 0xff));
  input->push_back(static_cast<char>((frame.size() >> 8) & 0xff));
  *input += frame;
}

void WriteSeeds(const std::string& dir) {
  Server server;
  (void)server.NextFrame();  // the base keyframe the target applies itself
  std::string moves, cut, key_again;
  for (int k = 0; k < 3; ++k) {
    server.x_m(2, 14 + k) -= 1e-4 * (k + 1);
    Append(&moves, server.NextFrame());
  }
  // A cut: remove two triangles and a vertex's use, add a vertex and a triangle.
  server.topology.RemoveTriangle(20);
  server.topology.RemoveTriangle(21);
  const std::uint32_t v = server.topology.AddVertex();
  server.x_m.col(v) = Eigen::Vector3d(0.0045, 0.0075, 0.0);
  server.topology.AddTriangle(v, 12, 13, 1);
  Append(&cut, server.NextFrame());
  server.x_m(2, v) -= 2e-4;
  Append(&cut, server.NextFrame());
  Append(&key_again, BaseKeyframe());
  Append(&key_again, server.NextFrame());
  int n = 0;
  for (const std::string* s : {&moves, &cut, &key_again}) {
    std::ofstream(dir + "/seed" + std::to_string(n++), std::ios::binary) << *s;
  }
}

bool Sound(const viewer::CompactMesh& m) {
  if (!m.vertices_m.allFinite()) return false;
  for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
    const auto a = m.triangles[t], b = m.triangles[t + 1], c = m.triangles[t + 2];
    const auto n = static_cast<std::uint32_t>(m.vertices_m.cols());
    if (a >= n || b >= n || c >= n || a == b || b == c || a == c) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("HAPSIM_FUZZ_WRITE_SEEDS")) {
    WriteSeeds(dir);
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  viewer::MeshCache cache;
  v1::Frame frame;
  if (!frame.ParseFromString(BaseKeyframe()) || cache.Apply(frame) != viewer::ApplyResult::kApplied) std::abort();
  std::size_t at = 0;
  for (int frames = 0; at + 2 <= size && frames < 16; ++frames) {
    const std::size_t length = data[at] | (static_cast<std::size_t>(data[at + 1]) << 8);
    at += 2;
    if (length > size - at) break;
    const bool parsed = frame.ParseFromArray(data + at, static_cast<int>(length));
    at += length;
    if (!parsed) continue;
    const viewer::CompactMesh before = cache.Compact();
    const std::uint64_t seq_before = cache.last_seq();
    const viewer::ApplyResult r = cache.Apply(frame);
    const viewer::CompactMesh after = cache.Compact();
    if (!Sound(after)) std::abort();
    if (r != viewer::ApplyResult::kApplied) {
      // Refused whole: nothing changed.
      if (cache.last_seq() != seq_before || after.triangles != before.triangles ||
          after.vertices_m.cols() != before.vertices_m.cols() || !(after.vertices_m.array() == before.vertices_m.array()).all())
        std::abort();
    }
  }
  return 0;
}
