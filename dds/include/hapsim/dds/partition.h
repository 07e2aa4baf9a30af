// The DDS partition of a session: every endpoint of a session (the server's
// pose reader and model writer, its bridge's pose writer and model reader)
// joins it, so a bridge receives only its own session's force models.
#pragma once
#include <string>
#include <string_view>

namespace hapsim::dds {

// "hapsim_s_" followed by the id with every byte outside [A-Za-z0-9-]
// written as _XX (two upper-case hex digits). One-to-one ('_' itself is
// escaped), and the result never holds '*' or '?', which Cyclone would treat
// as a pattern (it has no escape, and a pattern never matches a pattern) —
// so a session's partition matches only itself. Defined for any string,
// valid id or not (a bridge may be given anything).
std::string SessionPartition(std::string_view session_id);

}  // namespace hapsim::dds
