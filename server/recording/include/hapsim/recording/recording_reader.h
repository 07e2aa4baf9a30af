// Reads a trial recording (recording_format.h) record by record, checking
// each: its CRC-32, its bounds, that tick blocks follow each other without a
// hole, that a checkpoint names a tick already recorded, that nothing
// follows the end record. Reading stops at the first record that fails and
// says which one and why; everything before it is delivered and usable (a
// server killed mid-write leaves a torn last record — that is expected, not
// an error of the trial). Never trusts a length before checking it against
// the bytes that are there and the format's bounds, so any input is safe.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hapsim/recording/recording_format.h"

namespace hapsim::service {

struct RecordedCheckpoint {
  std::uint64_t tick = 0;  // the hash was taken right after this tick
  std::uint64_t state_hash = 0;
  double sim_time_s = 0.0;
};

// What a reader meets, in file order. Each callback may be empty.
struct RecordingVisitor {
  std::function<void(std::span<const TickInput>)> ticks;  // consecutive, continuing the previous block
  std::function<void(const RecordedCheckpoint&)> checkpoint;
  std::function<void(std::uint64_t first_tick, std::uint32_t count)> gap;  // no tick after it is delivered
  std::function<void(std::uint64_t next_tick, std::int64_t unix_ms)> resumed;
  // Every good record as it lies in the file (after the callbacks above):
  // its kind, its payload's offset and bytes, its first tick and count.
  std::function<void(RecordKind, std::uint64_t payload_offset, std::span<const std::uint8_t> payload,
                     std::uint64_t first_tick, std::uint32_t count)>
      record;
};

struct RecordingSummary {
  RecordingHeader header;
  std::uint64_t records = 0;  // good records read
  std::uint64_t ticks = 0;    // ticks delivered (from header.first_tick, consecutive)
  std::uint64_t checkpoints = 0;
  std::uint64_t resumes = 0;
  std::uint64_t valid_bytes = 0;             // the file's length up to the end of the last good record
  bool ended = false;                        // the end record was read: the trial closed cleanly
  std::optional<std::uint64_t> gap_at_tick;  // inputs were lost from this tick on
  std::optional<RecordingError> damage;      // where and why reading stopped early (nullopt: read to the end)
  std::uint64_t next_tick() const { return header.first_tick + ticks; }
};

// Throws RecordingError (record -1) when the file header itself is missing,
// of another version or damaged: nothing in such a file can be trusted.
RecordingSummary ReadRecording(std::span<const std::uint8_t> bytes, const RecordingVisitor& visitor = {});

// The file header alone (throws as ReadRecording does for a bad one).
RecordingHeader ReadRecordingHeader(std::span<const std::uint8_t> bytes);

// The whole file's bytes; throws std::runtime_error naming the path when it
// cannot be read.
std::vector<std::uint8_t> ReadRecordingBytes(const std::string& path);

}  // namespace hapsim::service
