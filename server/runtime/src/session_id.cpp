#include "hapsim/runtime/session_id.h"

namespace hapsim::runtime {

namespace {
bool IsAlnumOrDash(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-';
}
}  // namespace

bool IsValidSessionId(std::string_view id) {
  if (id.empty() || id.size() > 63) return false;
  for (const char c : id) {
    if (!IsAlnumOrDash(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

std::string SessionPartition(std::string_view session_id) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "hapsim_s_";
  for (const char ch : session_id) {
    const auto c = static_cast<unsigned char>(ch);
    if (IsAlnumOrDash(c)) {
      out += static_cast<char>(c);
    } else {
      out += '_';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

}  // namespace hapsim::runtime
