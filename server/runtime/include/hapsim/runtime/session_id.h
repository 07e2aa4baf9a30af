// Session ids, shared by the server, the bridge and the load generator.
#pragma once
#include <string>
#include <string_view>

namespace hapsim::runtime {

// Valid ids: 1 to 63 characters of [A-Za-z0-9_-] (they travel in a 64-byte
// DDS field and appear in logs and file names).
bool IsValidSessionId(std::string_view id);

// The DDS partition of a session: "hapsim_s_" followed by the id with every
// byte outside [A-Za-z0-9-] written as _XX (two upper-case hex digits).
// One-to-one ('_' itself is escaped), and the result never holds '*' or '?',
// which Cyclone would treat as a pattern (it has no escape, and a pattern
// never matches a pattern) — so a session's partition matches only itself.
// Defined for any string, valid id or not (a bridge may be given anything).
std::string SessionPartition(std::string_view session_id);

}  // namespace hapsim::runtime
