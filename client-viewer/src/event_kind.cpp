#include "hapsim/viewer/event_kind.h"

namespace hapsim::viewer {

namespace {
constexpr EventKind kNamedEventKinds[] = {EventKind::kContactBegin, EventKind::kContactEnd, EventKind::kPuncture,
                                          EventKind::kCutStart,     EventKind::kCutEnd,     EventKind::kReset};
}  // namespace

EventKind ParseEventKind(std::string_view name) {
  for (const EventKind kind : kNamedEventKinds) {
    if (name == ToString(kind)) return kind;
  }
  return EventKind::kUnknown;
}

const char* ToString(EventKind kind) {
  switch (kind) {
    case EventKind::kContactBegin:
      return "contact_begin";
    case EventKind::kContactEnd:
      return "contact_end";
    case EventKind::kPuncture:
      return "puncture";
    case EventKind::kCutStart:
      return "cut_start";
    case EventKind::kCutEnd:
      return "cut_end";
    case EventKind::kReset:
      return "reset";
    case EventKind::kUnknown:
      break;
  }
  return "unknown";
}

bool MarksTissue(EventKind kind) {
  return kind == EventKind::kPuncture || kind == EventKind::kCutStart || kind == EventKind::kCutEnd;
}

}  // namespace hapsim::viewer
