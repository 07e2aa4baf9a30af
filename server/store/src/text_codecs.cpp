#include "hapsim/store/text_codecs.h"

#include <charconv>
#include <cstdio>
#include <stdexcept>

namespace hapsim::service::store_codec {
namespace {

constexpr std::string_view kHex = "0123456789ABCDEF";

// '%' and `specials` as %XX.
std::string Escape(std::string_view s, std::string_view specials) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    if (c == '%' || specials.find(c) != std::string_view::npos) {
      const auto u = static_cast<unsigned char>(c);
      out += '%';
      out += kHex[u >> 4];
      out += kHex[u & 0xF];
    } else {
      out += c;
    }
  }
  return out;
}

int HexDigit(char c) {
  const auto at = kHex.find(c >= 'a' && c <= 'f' ? static_cast<char>(c - 'a' + 'A') : c);
  return at == std::string_view::npos ? -1 : static_cast<int>(at);
}

std::string Unescape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      out += s[i];
      continue;
    }
    const int hi = i + 2 < s.size() ? HexDigit(s[i + 1]) : -1;
    const int lo = i + 2 < s.size() ? HexDigit(s[i + 2]) : -1;
    if (hi < 0 || lo < 0) throw std::invalid_argument("bad escape in '" + std::string(s) + "'");
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return out;
}

// %.17g without the locale (the decimal point is always '.').
void AppendDouble(std::string& out, double v) {
  char buffer[40];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::general, 17);
  out.append(buffer, result.ptr);
}

double ParseDouble(std::string_view text) {
  double v = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), v);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) {
    throw std::invalid_argument("not a number: '" + std::string(text) + "'");
  }
  return v;
}

// Calls `piece` on each `separator`-separated piece of a non-empty text.
template <class Piece>
void ForEachPiece(std::string_view text, char separator, Piece piece) {
  if (text.empty()) return;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t end = text.find(separator, begin);
    piece(text.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin));
    if (end == std::string_view::npos) return;
    begin = end + 1;
  }
}

}  // namespace

std::string EncodeParams(const std::map<std::string, double>& params) {
  std::string out;
  for (const auto& [name, value] : params) {
    if (!out.empty()) out += ';';
    out += Escape(name, ";=");
    out += '=';
    AppendDouble(out, value);
  }
  return out;
}

std::map<std::string, double> DecodeParams(std::string_view text) {
  std::map<std::string, double> params;
  ForEachPiece(text, ';', [&](std::string_view pair) {
    const std::size_t eq = pair.find('=');
    if (eq == std::string_view::npos) throw std::invalid_argument("param without '=': '" + std::string(pair) + "'");
    params[Unescape(pair.substr(0, eq))] = ParseDouble(pair.substr(eq + 1));
  });
  return params;
}

std::string EncodeDoubles(std::span<const double> values) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out += ',';
    AppendDouble(out, values[i]);
  }
  return out;
}

std::vector<double> DecodeDoubles(std::string_view text) {
  std::vector<double> values;
  ForEachPiece(text, ',', [&](std::string_view piece) { values.push_back(ParseDouble(piece)); });
  return values;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i) out += '|';
    out += Escape(names[i], "|");
  }
  return out;
}

std::vector<std::string> SplitNames(std::string_view text) {
  std::vector<std::string> names;
  ForEachPiece(text, '|', [&](std::string_view piece) { names.push_back(Unescape(piece)); });
  return names;
}

}  // namespace hapsim::service::store_codec
