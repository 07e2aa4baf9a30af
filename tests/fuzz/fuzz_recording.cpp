// Any bytes as a trial recording (.hrec, server/recording), as they are or
// (inputs of even length) with every checksum made right. Invariants: the
// reader either refuses the file header with a RecordingError of record -1,
// or returns what it read: the good prefix ends within the input, reading
// just that prefix finds the same records and no damage, and the delivered
// ticks and checkpoints written again read back bit for bit. Damage is
// reported at the byte where the good prefix ends. It never allocates
// beyond what the format's bounds allow (checked by -malloc_limit_mb).
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "fuzz_setup.h"
#include "hapsim/recording/recording_reader.h"

namespace {

using namespace hapsim::service;

void Append(std::vector<std::uint8_t>* out, const std::vector<std::uint8_t>& bytes) {
  out->insert(out->end(), bytes.begin(), bytes.end());
}

// A small real recording: two blocks of a moving tool, a checkpoint, a
// resume mark and the end; then the same cut short and with a flipped byte.
void WriteSeeds(const std::string& dir) {
  RecordingHeader h;
  h.session_id = "t1";
  h.run_id = "r1";
  h.scene = "tissue_block";
  h.params["grid_nodes"] = 6;
  h.owner = "alice";
  std::vector<std::uint8_t> file = EncodeFileHeader(h);
  std::vector<TickInput> ticks;
  for (std::uint64_t t = 0; t < 40; ++t) {
    TickInput in;
    in.tick = t;
    in.tool.valid = t > 3;
    in.tool.tip_W_m = Eigen::Vector3d(0.001 * t, 0, 0.002 - 1e-4 * t);
    in.pose_seq = t;
    in.fresh_pose = true;
    ticks.push_back(in);
  }
  Append(&file, EncodeRecord(RecordKind::kTicks, 0, 20, EncodeTickBlock(std::span(ticks).first(20))));
  Append(&file, EncodeRecord(RecordKind::kCheckpoint, 19, 1, EncodeCheckpoint(0x1234, 0.02)));
  Append(&file, EncodeRecord(RecordKind::kResumed, 20, 0, EncodeResumed(1764172800000)));
  Append(&file, EncodeRecord(RecordKind::kTicks, 20, 20, EncodeTickBlock(std::span(ticks).subspan(20))));
  Append(&file, EncodeRecord(RecordKind::kEnd, 0, 40, {}));
  auto write = [&](const std::string& name, const std::vector<std::uint8_t>& bytes) {
    std::ofstream(dir + "/" + name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  };
  write("whole", file);
  write("torn", std::vector<std::uint8_t>(file.begin(), file.end() - 30));
  auto flipped = file;
  flipped[flipped.size() / 2] ^= 0x40;
  write("flipped", flipped);
}

template <typename T>
void PutAt(std::vector<std::uint8_t>* bytes, std::size_t at, T value) {
  std::memcpy(bytes->data() + at, &value, sizeof value);
}

// The input with every checksum it can find made right: without this nearly
// every mutation dies at a CRC check and the decoders behind it (zstd, the
// tick columns, the record rules) are seldom reached.
std::vector<std::uint8_t> WithChecksumsFixed(std::span<const std::uint8_t> input) {
  std::vector<std::uint8_t> bytes(input.begin(), input.end());
  if (bytes.size() < 16) return bytes;
  std::uint32_t text = 0;
  std::memcpy(&text, bytes.data() + 12, 4);
  if (text > kMaxHeaderTextBytes || bytes.size() < 16 + std::size_t{text} + 4) return bytes;
  PutAt(&bytes, 16 + text, Crc32(std::span(bytes).subspan(16, text)));
  for (std::size_t at = 16 + text + 4; bytes.size() - at >= kRecordHeaderBytes;) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + at + 4, 4);
    if (length > bytes.size() - at - kRecordHeaderBytes) break;
    const auto payload = std::span(bytes).subspan(at + kRecordHeaderBytes, length);
    PutAt(&bytes, at + 20, Crc32(payload, Crc32(std::span(bytes).subspan(at, 20))));
    at += kRecordHeaderBytes + length;
  }
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hapsim::fuzz::SetUpServiceFuzzer(&WriteSeeds);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Inputs whose size is odd are read as they are; even ones with their checksums fixed.
  const std::vector<std::uint8_t> fixed = size % 2 ? std::vector<std::uint8_t>() : WithChecksumsFixed({data, size});
  const std::span<const std::uint8_t> input = size % 2 ? std::span<const std::uint8_t>(data, size) : fixed;
  std::vector<TickInput> ticks;
  std::vector<RecordedCheckpoint> checkpoints;
  RecordingVisitor visitor;
  visitor.ticks = [&](std::span<const TickInput> t) { ticks.insert(ticks.end(), t.begin(), t.end()); };
  visitor.checkpoint = [&](const RecordedCheckpoint& c) { checkpoints.push_back(c); };
  RecordingSummary s;
  try {
    s = ReadRecording(input, visitor);
  } catch (const RecordingError& e) {
    if (e.record_index() != -1) std::abort();  // only the file header throws
    return 0;
  }
  if (s.valid_bytes > input.size() || s.ticks != ticks.size() || s.checkpoints != checkpoints.size()) std::abort();
  if (s.damage && s.damage->byte_offset() != s.valid_bytes) std::abort();
  if (!s.damage && !s.gap_at_tick && s.valid_bytes != input.size()) std::abort();
  // The good prefix alone: the same records, nothing damaged.
  const RecordingSummary prefix = ReadRecording(input.first(s.valid_bytes));
  if (prefix.damage || prefix.records != s.records || prefix.ticks != s.ticks) std::abort();
  // Written again, read back: the same ticks, bit for bit.
  std::vector<std::uint8_t> again = EncodeFileHeader(s.header);
  for (std::size_t at = 0; at < ticks.size(); at += 1000) {
    const auto block = std::span(ticks).subspan(at, std::min<std::size_t>(1000, ticks.size() - at));
    Append(&again, EncodeRecord(RecordKind::kTicks, block.front().tick, static_cast<std::uint32_t>(block.size()),
                                EncodeTickBlock(block)));
  }
  std::vector<TickInput> reread;
  RecordingVisitor back;
  back.ticks = [&](std::span<const TickInput> t) { reread.insert(reread.end(), t.begin(), t.end()); };
  const RecordingSummary again_summary = ReadRecording(again, back);
  if (again_summary.damage || reread.size() != ticks.size()) std::abort();
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const TickInput &a = ticks[i], &b = reread[i];
    if (a.tick != b.tick || std::memcmp(a.tool.tip_W_m.data(), b.tool.tip_W_m.data(), 24) != 0 ||
        std::memcmp(a.tool.orientation_W.coeffs().data(), b.tool.orientation_W.coeffs().data(), 32) != 0 ||
        std::memcmp(a.tool.velocity_W_m_per_s.data(), b.tool.velocity_W_m_per_s.data(), 24) != 0 ||
        a.tool.valid != b.tool.valid || a.tool.buttons != b.tool.buttons || a.pose_seq != b.pose_seq ||
        a.device_id != b.device_id || a.paused != b.paused || a.reset != b.reset || a.fresh_pose != b.fresh_pose)
      std::abort();
  }
  return 0;
}
