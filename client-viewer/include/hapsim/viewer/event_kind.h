// The kinds of scene event a frame carries. They travel as names
// (SceneEvent.kind, docs/protocol.md); the viewer parses a name once, when it
// decodes the frame, and everything after matches the enum.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace hapsim::viewer {

enum class EventKind : std::uint8_t {
  kContactBegin,
  kContactEnd,
  kPuncture,
  kCutStart,  // a blade began an incision (where: its start)
  kCutEnd,    // the blade left it (where: its end; value: its length [m])
  kReset,
  kUnknown,  // a name this viewer does not know (a newer server)
};
inline constexpr std::size_t kEventKindCount = 7;

EventKind ParseEventKind(std::string_view name);
// The wire name; "unknown" for kUnknown.
const char* ToString(EventKind kind);
// Punctures and cuts leave a mark on the tissue worth drawing and listing
// prominently; contact begin/end happen at the tip all the time.
bool MarksTissue(EventKind kind);

}  // namespace hapsim::viewer
