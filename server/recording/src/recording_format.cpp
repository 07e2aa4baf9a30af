#include "hapsim/recording/recording_format.h"

#include <zstd.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace hapsim::service {

namespace {

static_assert(std::endian::native == std::endian::little, "the recording format is little-endian");

template <typename T>
void PutRaw(std::vector<std::uint8_t>* out, T value) {
  const auto at = out->size();
  out->resize(at + sizeof(T));
  std::memcpy(out->data() + at, &value, sizeof(T));
}

std::array<std::uint32_t, 256> MakeCrcTable() {
  std::array<std::uint32_t, 256> table{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

// One column of a tick block: a field read from and written to a TickInput,
// as an unsigned integer of `bytes` bytes (doubles by their bits).
struct Column {
  std::size_t bytes;
  std::uint64_t (*get)(const TickInput&);
  void (*set)(TickInput&, std::uint64_t);
};

std::uint64_t Bits(double v) { return std::bit_cast<std::uint64_t>(v); }
double FromBits(std::uint64_t b) { return std::bit_cast<double>(b); }

constexpr std::uint64_t kValid = 1, kFresh = 2, kPaused = 4, kReset = 8;

// The order of the columns is part of the format (version 1).
const std::array<Column, 14>& Columns() {
  static const std::array<Column, 14> columns = {{
      {1,
       [](const TickInput& t) {
         return (t.tool.valid ? kValid : 0) | (t.fresh_pose ? kFresh : 0) | (t.paused ? kPaused : 0) |
                (t.reset ? kReset : 0);
       },
       [](TickInput& t, std::uint64_t v) {
         t.tool.valid = v & kValid;
         t.fresh_pose = v & kFresh;
         t.paused = v & kPaused;
         t.reset = v & kReset;
       }},
      {4, [](const TickInput& t) -> std::uint64_t { return t.device_id; },
       [](TickInput& t, std::uint64_t v) { t.device_id = static_cast<std::uint32_t>(v); }},
      {8, [](const TickInput& t) { return t.pose_seq; }, [](TickInput& t, std::uint64_t v) { t.pose_seq = v; }},
      {8, [](const TickInput& t) { return Bits(t.tool.tip_W_m.x()); },
       [](TickInput& t, std::uint64_t v) { t.tool.tip_W_m.x() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.tip_W_m.y()); },
       [](TickInput& t, std::uint64_t v) { t.tool.tip_W_m.y() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.tip_W_m.z()); },
       [](TickInput& t, std::uint64_t v) { t.tool.tip_W_m.z() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.orientation_W.w()); },
       [](TickInput& t, std::uint64_t v) { t.tool.orientation_W.w() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.orientation_W.x()); },
       [](TickInput& t, std::uint64_t v) { t.tool.orientation_W.x() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.orientation_W.y()); },
       [](TickInput& t, std::uint64_t v) { t.tool.orientation_W.y() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.orientation_W.z()); },
       [](TickInput& t, std::uint64_t v) { t.tool.orientation_W.z() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.velocity_W_m_per_s.x()); },
       [](TickInput& t, std::uint64_t v) { t.tool.velocity_W_m_per_s.x() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.velocity_W_m_per_s.y()); },
       [](TickInput& t, std::uint64_t v) { t.tool.velocity_W_m_per_s.y() = FromBits(v); }},
      {8, [](const TickInput& t) { return Bits(t.tool.velocity_W_m_per_s.z()); },
       [](TickInput& t, std::uint64_t v) { t.tool.velocity_W_m_per_s.z() = FromBits(v); }},
      {4, [](const TickInput& t) -> std::uint64_t { return t.tool.buttons; },
       [](TickInput& t, std::uint64_t v) { t.tool.buttons = static_cast<std::uint32_t>(v); }},
  }};
  return columns;
}

// The low `bytes` bytes set: a column's width.
std::uint64_t WidthMask(std::size_t bytes) {
  return bytes == 8 ? ~std::uint64_t{0} : (std::uint64_t{1} << (8 * bytes)) - 1;
}

std::uint64_t ColumnMask(const Column& column) { return WidthMask(column.bytes); }

// A residual modulo 2^(8 bytes) as a signed number, folded so that 0, -1, 1,
// -2, ... become 0, 1, 2, 3, ...
std::uint64_t ZigZag(std::uint64_t r, std::size_t bytes) {
  const std::uint64_t mask = WidthMask(bytes);
  const bool negative = (r >> (8 * bytes - 1)) & 1u;
  return ((r << 1) ^ (negative ? mask : 0)) & mask;
}

std::uint64_t UnZigZag(std::uint64_t z, std::size_t bytes) {
  const std::uint64_t mask = WidthMask(bytes);
  return ((z >> 1) ^ ((z & 1u) ? mask : 0)) & mask;
}

std::size_t RawBytesPerTick() {
  std::size_t n = 0;
  for (const auto& c : Columns()) n += c.bytes;
  return n;
}

bool FiniteTool(const core::ToolInput& tool) {
  return tool.tip_W_m.allFinite() && tool.orientation_W.coeffs().allFinite() && tool.velocity_W_m_per_s.allFinite();
}

}  // namespace

const char* RecordKindName(RecordKind kind) {
  switch (kind) {
    case RecordKind::kTicks:
      return "ticks";
    case RecordKind::kCheckpoint:
      return "checkpoint";
    case RecordKind::kGap:
      return "gap";
    case RecordKind::kResumed:
      return "resumed";
    case RecordKind::kEnd:
      return "end";
  }
  return "unknown";
}

RecordingError::RecordingError(std::int64_t record_index, std::uint64_t byte_offset, const std::string& what)
    : std::runtime_error((record_index < 0 ? std::string("file header") : "record " + std::to_string(record_index)) +
                         " at byte " + std::to_string(byte_offset) + ": " + what),
      record_index_(record_index),
      byte_offset_(byte_offset) {}

std::uint32_t Crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
  static const std::array<std::uint32_t, 256> table = MakeCrcTable();
  crc = ~crc;
  for (std::uint8_t b : bytes) crc = table[(crc ^ b) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

std::vector<std::uint8_t> EncodeFileHeader(const RecordingHeader& h) {
  std::string text;
  auto line = [&text](const std::string& key, const std::string& value) {
    if (key.find_first_of("=\n") != std::string::npos || value.find('\n') != std::string::npos) {
      throw std::invalid_argument("recording header field " + key + " holds a line break or '='");
    }
    text += key + "=" + value + "\n";
  };
  auto number = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  line("session_id", h.session_id);
  line("run_id", h.run_id);
  line("trial", std::to_string(h.trial));
  line("scene", h.scene);
  for (const auto& [name, value] : h.params) line("param." + name, number(value));
  line("owner", h.owner);
  line("class", h.class_name);
  line("tick_period_s", number(h.tick_period_s));
  line("first_tick", std::to_string(h.first_tick));
  line("started_unix_ms", std::to_string(h.started_unix_ms));
  line("checkpoint_every_ticks", std::to_string(h.checkpoint_every_ticks));
  line("written_by", h.written_by);
  std::vector<std::uint8_t> out(kRecordingMagic.begin(), kRecordingMagic.end());
  PutRaw(&out, kRecordingVersion);
  PutRaw(&out, static_cast<std::uint32_t>(text.size()));
  out.insert(out.end(), text.begin(), text.end());
  PutRaw(&out, Crc32({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}));
  return out;
}

std::vector<std::uint8_t> EncodeRecord(RecordKind kind, std::uint64_t first_tick, std::uint32_t count,
                                       std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out;
  out.reserve(kRecordHeaderBytes + payload.size());
  PutRaw(&out, static_cast<std::uint8_t>(kind));
  out.insert(out.end(), 3, std::uint8_t{0});
  PutRaw(&out, static_cast<std::uint32_t>(payload.size()));
  PutRaw(&out, first_tick);
  PutRaw(&out, count);
  const std::uint32_t crc = Crc32(payload, Crc32(out));
  PutRaw(&out, crc);
  out.insert(out.end(), payload.begin(), payload.end());
  return out;
}

TickBlockEncoder::TickBlockEncoder() : context_(ZSTD_createCCtx()) {
  if (!context_) throw std::bad_alloc();
  ZSTD_CCtx_setParameter(context_, ZSTD_c_compressionLevel, kCompressionLevel);
}

TickBlockEncoder::~TickBlockEncoder() { ZSTD_freeCCtx(context_); }

std::span<const std::uint8_t> TickBlockEncoder::Encode(std::span<const TickInput> ticks) {
  if (ticks.size() > kMaxTicksPerBlock) throw std::invalid_argument("too many ticks for one block");
  for (std::size_t i = 1; i < ticks.size(); ++i) {
    if (ticks[i].tick != ticks[0].tick + i) throw std::invalid_argument("a tick block's ticks must be consecutive");
  }
  // Each value as its residual from a straight-line prediction from the two
  // before it (integers modulo the column's width: exactly reversible; a held
  // or steadily moving pose gives residuals near zero), zigzag-coded so small
  // negative residuals are small too, then byte plane by byte plane.
  const std::size_t n = ticks.size();
  raw_.resize(n * RawBytesPerTick());
  residual_.resize(n);
  std::size_t at = 0;
  for (const Column& column : Columns()) {
    const std::uint64_t mask = ColumnMask(column);
    std::uint64_t before = 0, previous = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t v = column.get(ticks[i]) & mask;
      residual_[i] = ZigZag((v - (2 * previous - before)) & mask, column.bytes);
      before = previous;
      previous = v;
    }
    for (std::size_t b = 0; b < column.bytes; ++b) {
      for (std::size_t i = 0; i < n; ++i) raw_[at++] = static_cast<std::uint8_t>((residual_[i] >> (8 * b)) & 0xFFu);
    }
  }
  out_.clear();
  PutRaw(&out_, static_cast<std::uint32_t>(raw_.size()));
  const std::size_t header = out_.size();
  out_.resize(header + ZSTD_compressBound(raw_.size()));
  const std::size_t written =
      ZSTD_compress2(context_, out_.data() + header, out_.size() - header, raw_.data(), raw_.size());
  if (ZSTD_isError(written)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(written));
  out_.resize(header + written);
  return out_;
}

std::vector<std::uint8_t> EncodeTickBlock(std::span<const TickInput> ticks) {
  TickBlockEncoder encoder;
  const auto payload = encoder.Encode(ticks);
  return {payload.begin(), payload.end()};
}

TickBlockDecoder::TickBlockDecoder() : context_(ZSTD_createDCtx()) {
  if (!context_) throw std::bad_alloc();
}

void TickBlockDecoder::ReserveForLargestBlock() {
  raw_.reserve(kMaxTicksPerBlock * RawBytesPerTick());
  values_.reserve(kMaxTicksPerBlock);
  ticks_.reserve(kMaxTicksPerBlock);
  // zstd sizes its decompression context at the first frame: decode one now.
  const std::vector<TickInput> one(1);
  const auto frame = EncodeTickBlock(one);
  Decode(frame, 0, 1);
}

TickBlockDecoder::~TickBlockDecoder() { ZSTD_freeDCtx(context_); }

std::span<const TickInput> TickBlockDecoder::Decode(std::span<const std::uint8_t> payload, std::uint64_t first_tick,
                                                    std::uint32_t count) {
  if (count == 0 || count > kMaxTicksPerBlock) {
    throw std::runtime_error("a tick block of " + std::to_string(count) + " ticks (1.." +
                             std::to_string(kMaxTicksPerBlock) + " allowed)");
  }
  std::uint32_t raw_bytes = 0;
  if (payload.size() < sizeof raw_bytes) throw std::runtime_error("a tick block shorter than its length field");
  std::memcpy(&raw_bytes, payload.data(), sizeof raw_bytes);
  const std::size_t expected = count * RawBytesPerTick();
  if (raw_bytes != expected) {
    throw std::runtime_error("a tick block of " + std::to_string(count) + " ticks says " + std::to_string(raw_bytes) +
                             " bytes (expected " + std::to_string(expected) + ")");
  }
  const auto compressed = payload.subspan(sizeof raw_bytes);
  const unsigned long long content = ZSTD_getFrameContentSize(compressed.data(), compressed.size());
  if (content != expected) throw std::runtime_error("a tick block whose zstd frame is damaged or of the wrong size");
  raw_.resize(expected);  // after ReserveForLargestBlock(): within capacity, no allocation
  const std::size_t got = ZSTD_decompressDCtx(context_, raw_.data(), raw_.size(), compressed.data(), compressed.size());
  if (ZSTD_isError(got) || got != expected) throw std::runtime_error("a tick block that does not decompress");

  ticks_.assign(count, TickInput{});
  values_.resize(count);
  std::size_t at = 0;
  for (const Column& column : Columns()) {
    std::fill(values_.begin(), values_.end(), 0);
    for (std::size_t b = 0; b < column.bytes; ++b) {
      for (std::size_t i = 0; i < count; ++i) values_[i] |= static_cast<std::uint64_t>(raw_[at++]) << (8 * b);
    }
    const std::uint64_t mask = ColumnMask(column);
    std::uint64_t before = 0, previous = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint64_t v = (UnZigZag(values_[i], column.bytes) + 2 * previous - before) & mask;
      column.set(ticks_[i], v);
      before = previous;
      previous = v;
    }
  }
  for (std::uint32_t i = 0; i < count; ++i) {
    ticks_[i].tick = first_tick + i;
    if (!FiniteTool(ticks_[i].tool)) {
      throw std::runtime_error("tick " + std::to_string(first_tick + i) + " holds a non-finite pose");
    }
  }
  return ticks_;
}

std::vector<TickInput> DecodeTickBlock(std::span<const std::uint8_t> payload, std::uint64_t first_tick,
                                       std::uint32_t count) {
  TickBlockDecoder decoder;
  const auto ticks = decoder.Decode(payload, first_tick, count);
  return {ticks.begin(), ticks.end()};
}

std::vector<std::uint8_t> EncodeCheckpoint(std::uint64_t state_hash, double sim_time_s) {
  std::vector<std::uint8_t> out;
  PutRaw(&out, state_hash);
  PutRaw(&out, sim_time_s);
  return out;
}

std::vector<std::uint8_t> EncodeResumed(std::int64_t unix_ms) {
  std::vector<std::uint8_t> out;
  PutRaw(&out, unix_ms);
  return out;
}

}  // namespace hapsim::service
