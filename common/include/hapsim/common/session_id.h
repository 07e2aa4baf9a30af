// Session ids, shared by the server, the bridge, the load generator and the
// viewer.
#pragma once
#include <string_view>

namespace hapsim::common {

// Valid ids: 1 to 63 characters of [A-Za-z0-9_-] (they travel in a 64-byte
// DDS field and appear in logs and file names).
bool IsValidSessionId(std::string_view id);

// The bytes a session id may hold besides '_': [A-Za-z0-9-]. (The DDS
// partition name escapes every other byte, '_' included.)
constexpr bool IsAlnumOrDash(unsigned char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-';
}

}  // namespace hapsim::common
