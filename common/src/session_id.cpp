#include "hapsim/common/session_id.h"

namespace hapsim::common {

bool IsValidSessionId(std::string_view id) {
  if (id.empty() || id.size() > 63) return false;
  for (const char c : id) {
    if (!IsAlnumOrDash(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

}  // namespace hapsim::common
