// The trial recording file (.hrec): everything needed to re-run a trial
// exactly — the scene it ran and every tick's TickInput — plus the scene's
// state hash at checkpoints, to prove a replay reached the same state.
// docs/recording.md documents the layout byte by byte.
//
//   file    = file header, then records until the end of the file
//   header  = "HAPSIMRC" | u32 version | u32 text length | text | u32 CRC-32 of the text
//             (text: "key=value" lines, RecordingHeader below)
//   record  = u8 kind | 3 zero bytes | u32 payload length | u64 first tick | u32 count
//             | u32 CRC-32 of the 20 bytes before it and the payload | payload
//
// Append-only: a record is written whole or is the torn tail a reader stops
// at; every record is checked on its own (CRC-32), so corruption is found at
// the exact record and the records before it stay usable. Little-endian.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "hapsim/runtime/tick_input.h"

struct ZSTD_CCtx_s;  // zstd's compression and decompression contexts (zstd.h)
struct ZSTD_DCtx_s;

namespace hapsim::service {

inline constexpr std::array<char, 8> kRecordingMagic = {'H', 'A', 'P', 'S', 'I', 'M', 'R', 'C'};
inline constexpr std::uint32_t kRecordingVersion = 1;
inline constexpr std::size_t kRecordHeaderBytes = 24;
// Bounds a reader enforces before allocating anything: far above what a
// writer produces (a block holds at most kMaxTicksPerBlock ticks).
inline constexpr std::uint32_t kMaxHeaderTextBytes = 64 * 1024;
inline constexpr std::uint32_t kMaxRecordPayloadBytes = 4 * 1024 * 1024;
inline constexpr std::uint32_t kMaxTicksPerBlock = 8192;

enum class RecordKind : std::uint8_t {
  kTicks = 1,       // a block of consecutive ticks' inputs (zstd; layout in EncodeTickBlock)
  kCheckpoint = 2,  // the scene's StateHash() right after a tick: u64 hash | f64 sim time [s]
  kGap = 3,         // `count` ticks from `first tick` were not recorded (the writer fell behind):
                    // a replay cannot go past it
  kResumed = 4,     // the server restarted and restored the session here: i64 wall clock [unix ms]
  kEnd = 5,         // the trial ended cleanly after `first tick` + `count` ticks; nothing follows
};
const char* RecordKindName(RecordKind kind);

// What the file header says: enough to build the same scene again.
struct RecordingHeader {
  std::string session_id;
  std::string run_id;  // one incarnation of the session (kept when a restart restores it)
  std::uint64_t trial = 0;
  std::string scene;
  std::map<std::string, double> params;
  std::string owner;
  std::string class_name;
  double tick_period_s = 0.001;
  std::uint64_t first_tick = 0;  // the session's tick index of the trial's first tick
  std::int64_t started_unix_ms = 0;
  std::uint32_t checkpoint_every_ticks = 1000;
  std::string written_by;  // "hapsim-server VERSION"
};

// One tick as recorded: its input, and the state hash after it when the tick
// is a checkpoint.
struct TickRecord {
  TickInput input;
  bool has_hash = false;
  std::uint64_t state_hash = 0;
  double sim_time_s = 0.0;
};

// A record that cannot be read, with where: the record's index (0 = the
// first after the header; -1 = the file header) and its byte offset.
class RecordingError : public std::runtime_error {
 public:
  RecordingError(std::int64_t record_index, std::uint64_t byte_offset, const std::string& what);
  std::int64_t record_index() const { return record_index_; }
  std::uint64_t byte_offset() const { return byte_offset_; }

 private:
  std::int64_t record_index_;
  std::uint64_t byte_offset_;
};

std::uint32_t Crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

// The file header's bytes; throws std::invalid_argument when a text field
// holds a line break or '=' in a key (it could not be read back).
std::vector<std::uint8_t> EncodeFileHeader(const RecordingHeader& header);

// One record's bytes (header + payload).
std::vector<std::uint8_t> EncodeRecord(RecordKind kind, std::uint64_t first_tick, std::uint32_t count,
                                       std::span<const std::uint8_t> payload);

// A block of consecutive ticks' inputs as a kTicks payload: u32 raw length
// | zstd frame of the fields as columns (struct of arrays), each value
// replaced by its zigzag residual from a straight-line prediction from the
// two before it, split into byte planes — so zstd sees long runs of zeros. `ticks` must be consecutive
// (ticks[i].tick == ticks[0].tick + i) and at most kMaxTicksPerBlock.
std::vector<std::uint8_t> EncodeTickBlock(std::span<const TickInput> ticks);

// EncodeTickBlock for a writer that encodes block after block: its zstd
// context and buffers are made once (a fresh context per block costs more
// than compressing one).
class TickBlockEncoder {
 public:
  static constexpr int kCompressionLevel = -1;  // zstd's fastest-but-one: as small as level 1 here, a third faster
  TickBlockEncoder();
  ~TickBlockEncoder();
  TickBlockEncoder(const TickBlockEncoder&) = delete;
  TickBlockEncoder& operator=(const TickBlockEncoder&) = delete;
  // The payload, valid until the next call.
  std::span<const std::uint8_t> Encode(std::span<const TickInput> ticks);

 private:
  ZSTD_CCtx_s* context_;
  std::vector<std::uint8_t> raw_, out_;
  std::vector<std::uint64_t> residual_;
};
// The inverse; throws std::runtime_error (what is wrong) on a payload that
// does not decode to exactly `count` ticks starting at `first_tick`.
std::vector<TickInput> DecodeTickBlock(std::span<const std::uint8_t> payload, std::uint64_t first_tick,
                                       std::uint32_t count);

// DecodeTickBlock for a reader that decodes block after block: one zstd
// context and reused buffers. After ReserveForLargestBlock() decoding never
// allocates (only a damaged payload's error message does): for a tick thread.
class TickBlockDecoder {
 public:
  TickBlockDecoder();
  void ReserveForLargestBlock();
  ~TickBlockDecoder();
  TickBlockDecoder(const TickBlockDecoder&) = delete;
  TickBlockDecoder& operator=(const TickBlockDecoder&) = delete;
  // The ticks, valid until the next call; throws as DecodeTickBlock does.
  std::span<const TickInput> Decode(std::span<const std::uint8_t> payload, std::uint64_t first_tick,
                                    std::uint32_t count);

 private:
  ZSTD_DCtx_s* context_;
  std::vector<std::uint8_t> raw_;
  std::vector<std::uint64_t> values_;
  std::vector<TickInput> ticks_;
};

std::vector<std::uint8_t> EncodeCheckpoint(std::uint64_t state_hash, double sim_time_s);
std::vector<std::uint8_t> EncodeResumed(std::int64_t unix_ms);

}  // namespace hapsim::service
