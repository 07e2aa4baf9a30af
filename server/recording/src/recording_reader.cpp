#include "hapsim/recording/recording_reader.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

namespace hapsim::service {

namespace {

template <typename T>
T GetRaw(std::span<const std::uint8_t> bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

bool ParseUnsigned(const std::string& text, std::uint64_t* out) {
  if (text.empty() || text.size() > 20) return false;
  std::uint64_t v = 0;
  for (char c : text) {
    if (c < '0' || c > '9') return false;
    const std::uint64_t digit = static_cast<std::uint64_t>(c - '0');
    if (v > (UINT64_MAX - digit) / 10) return false;
    v = v * 10 + digit;
  }
  *out = v;
  return true;
}

bool ParseNumber(const std::string& text, double* out) {
  if (text.empty() || text.size() > 40) return false;
  char* end = nullptr;
  *out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(*out);
}

RecordingHeader ParseHeaderText(const std::string& text, std::uint64_t offset) {
  RecordingHeader h;
  bool have_scene = false, have_period = false;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = text.find('\n', at);
    if (end == std::string::npos) throw RecordingError(-1, offset, "header text does not end with a line break");
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) throw RecordingError(-1, offset, "header line without '='");
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    std::uint64_t u = 0;
    double d = 0.0;
    auto bad = [&](const char* what) { return RecordingError(-1, offset, "header field " + key + ": " + what); };
    if (key == "session_id") {
      h.session_id = value;
    } else if (key == "run_id") {
      h.run_id = value;
    } else if (key == "trial") {
      if (!ParseUnsigned(value, &h.trial)) throw bad("not a count");
    } else if (key == "scene") {
      h.scene = value;
      have_scene = !value.empty();
    } else if (key.rfind("param.", 0) == 0) {
      if (!ParseNumber(value, &d)) throw bad("not a finite number");
      h.params[key.substr(6)] = d;
    } else if (key == "owner") {
      h.owner = value;
    } else if (key == "class") {
      h.class_name = value;
    } else if (key == "tick_period_s") {
      if (!ParseNumber(value, &h.tick_period_s) || h.tick_period_s <= 0.0 || h.tick_period_s > 1.0) {
        throw bad("not a period in (0, 1] s");
      }
      have_period = true;
    } else if (key == "first_tick") {
      if (!ParseUnsigned(value, &h.first_tick)) throw bad("not a count");
    } else if (key == "started_unix_ms") {
      if (!ParseUnsigned(value, &u) || u > static_cast<std::uint64_t>(INT64_MAX)) throw bad("not a time");
      h.started_unix_ms = static_cast<std::int64_t>(u);
    } else if (key == "checkpoint_every_ticks") {
      if (!ParseUnsigned(value, &u) || u == 0 || u > 1000000) throw bad("not a count in 1..1000000");
      h.checkpoint_every_ticks = static_cast<std::uint32_t>(u);
    } else if (key == "written_by") {
      h.written_by = value;
    }  // other keys: written by a newer build of the same version; ignored
  }
  if (!have_scene || !have_period) throw RecordingError(-1, offset, "header lacks the scene or the tick period");
  return h;
}

// The file header; returns the offset of the first record.
std::size_t ReadFileHeader(std::span<const std::uint8_t> bytes, RecordingHeader* header) {
  constexpr std::size_t kFixed = kRecordingMagic.size() + 8;
  if (bytes.size() < kFixed || std::memcmp(bytes.data(), kRecordingMagic.data(), kRecordingMagic.size()) != 0) {
    throw RecordingError(-1, 0, "not a hapsim trial recording (no HAPSIMRC magic)");
  }
  const auto version = GetRaw<std::uint32_t>(bytes, 8);
  if (version != kRecordingVersion) {
    throw RecordingError(
        -1, 8,
        "format version " + std::to_string(version) + " (this build reads " + std::to_string(kRecordingVersion) + ")");
  }
  const auto text_bytes = GetRaw<std::uint32_t>(bytes, 12);
  if (text_bytes > kMaxHeaderTextBytes) throw RecordingError(-1, 12, "header text longer than the format allows");
  if (bytes.size() < kFixed + text_bytes + 4) throw RecordingError(-1, kFixed, "file ends inside its header");
  const auto text = bytes.subspan(kFixed, text_bytes);
  if (Crc32(text) != GetRaw<std::uint32_t>(bytes, kFixed + text_bytes)) {
    throw RecordingError(-1, kFixed, "header checksum mismatch");
  }
  *header = ParseHeaderText(std::string(text.begin(), text.end()), kFixed);
  return kFixed + text_bytes + 4;
}

}  // namespace

RecordingSummary ReadRecording(std::span<const std::uint8_t> bytes, const RecordingVisitor& visitor) {
  RecordingSummary s;
  std::size_t at = ReadFileHeader(bytes, &s.header);
  s.valid_bytes = at;
  std::int64_t index = 0;
  TickBlockDecoder decoder;
  auto stop = [&](const std::string& what) { s.damage = RecordingError(index, at, what); };
  while (at < bytes.size()) {
    if (s.ended) return stop("data after the end record"), s;
    if (s.gap_at_tick) return s;  // nothing after a gap can be replayed
    if (bytes.size() - at < kRecordHeaderBytes) return stop("file ends inside a record header (torn write)"), s;
    const auto kind = static_cast<RecordKind>(bytes[at]);
    const auto length = GetRaw<std::uint32_t>(bytes, at + 4);
    const auto first_tick = GetRaw<std::uint64_t>(bytes, at + 8);
    const auto count = GetRaw<std::uint32_t>(bytes, at + 16);
    if (bytes[at + 1] != 0 || bytes[at + 2] != 0 || bytes[at + 3] != 0) return stop("damaged record header"), s;
    if (length > kMaxRecordPayloadBytes) return stop("payload length beyond the format's bound"), s;
    if (bytes.size() - at - kRecordHeaderBytes < length) return stop("file ends inside a record (torn write)"), s;
    const auto payload = bytes.subspan(at + kRecordHeaderBytes, length);
    if (Crc32(payload, Crc32(bytes.subspan(at, 20))) != GetRaw<std::uint32_t>(bytes, at + 20)) {
      return stop("checksum mismatch"), s;
    }
    const std::uint64_t expected = s.next_tick();
    switch (kind) {
      case RecordKind::kTicks: {
        if (first_tick != expected) {
          return stop("ticks from " + std::to_string(first_tick) + ", expected " + std::to_string(expected)), s;
        }
        std::span<const TickInput> ticks;
        try {
          ticks = decoder.Decode(payload, first_tick, count);
        } catch (const std::exception& e) {
          return stop(e.what()), s;
        }
        if (visitor.ticks) visitor.ticks(ticks);
        s.ticks += count;
        break;
      }
      case RecordKind::kCheckpoint: {
        if (length != 16 || count != 1) return stop("malformed checkpoint"), s;
        if (first_tick < s.header.first_tick || first_tick >= expected) {
          return stop("checkpoint after tick " + std::to_string(first_tick) + ", which is not recorded"), s;
        }
        const RecordedCheckpoint c{first_tick, GetRaw<std::uint64_t>(payload, 0), GetRaw<double>(payload, 8)};
        if (visitor.checkpoint) visitor.checkpoint(c);
        ++s.checkpoints;
        break;
      }
      case RecordKind::kGap:
        if (length != 0 || first_tick != expected || count == 0) return stop("malformed gap"), s;
        s.gap_at_tick = first_tick;
        if (visitor.gap) visitor.gap(first_tick, count);
        break;
      case RecordKind::kResumed:
        if (length != 8 || first_tick != expected) return stop("malformed resume mark"), s;
        if (visitor.resumed) visitor.resumed(first_tick, GetRaw<std::int64_t>(payload, 0));
        ++s.resumes;
        break;
      case RecordKind::kEnd:
        if (length != 0 || first_tick != s.header.first_tick || count != s.ticks) return stop("malformed end"), s;
        s.ended = true;
        break;
      default:
        return stop("unknown record kind " + std::to_string(static_cast<int>(kind))), s;
    }
    if (visitor.record) visitor.record(kind, at + kRecordHeaderBytes, payload, first_tick, count);
    at += kRecordHeaderBytes + length;
    s.valid_bytes = at;
    ++s.records;
    ++index;
  }
  return s;
}

RecordingHeader ReadRecordingHeader(std::span<const std::uint8_t> bytes) {
  RecordingHeader header;
  ReadFileHeader(bytes, &header);
  return header;
}

std::vector<std::uint8_t> ReadRecordingBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read recording " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace hapsim::service
