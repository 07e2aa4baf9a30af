#include "hapsim/bridge/json_writer.h"

#include <cmath>
#include <cstdio>

namespace hapsim::bridge {

namespace {

std::string Quoted(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      q += buf;
    } else {
      q += c;
    }
  }
  return q + "\"";
}

}  // namespace

void JsonWriter::Prefix(const char* key) {
  if (!has_members_.empty()) {
    if (has_members_.back()) out_ += ',';
    has_members_.back() = true;
    out_ += '\n';
    out_.append(2 * has_members_.size(), ' ');
  }
  if (key) out_ += Quoted(key) + ": ";
}

void JsonWriter::Open(const char* key, char bracket) {
  Prefix(key);
  out_ += bracket;
  has_members_.push_back(false);
}

void JsonWriter::Close(char bracket) {
  const bool had_members = has_members_.back();
  has_members_.pop_back();
  if (had_members) {
    out_ += '\n';
    out_.append(2 * has_members_.size(), ' ');
  }
  out_ += bracket;
  if (has_members_.empty()) out_ += '\n';
}

void JsonWriter::BeginObject(const char* key) { Open(key, '{'); }
void JsonWriter::EndObject() { Close('}'); }
void JsonWriter::BeginArray(const char* key) { Open(key, '['); }
void JsonWriter::EndArray() { Close(']'); }

void JsonWriter::Field(const char* key, std::uint64_t value) {
  Prefix(key);
  out_ += std::to_string(value);
}

void JsonWriter::Field(const char* key, double value) {
  Prefix(key);
  if (!std::isfinite(value)) {
    out_ += "null";
    return;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  out_ += buf;
}

void JsonWriter::Field(const char* key, bool value) {
  Prefix(key);
  out_ += value ? "true" : "false";
}

void JsonWriter::Field(const char* key, const std::string& value) {
  Prefix(key);
  out_ += Quoted(value);
}

}  // namespace hapsim::bridge
