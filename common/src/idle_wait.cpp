#include "hapsim/common/idle_wait.h"

namespace hapsim::common {

std::optional<IdleWait> ParseIdleWait(std::string_view name) {
  if (name == "sleep") return IdleWait::kSleep;
  if (name == "spin") return IdleWait::kSpin;
  return std::nullopt;
}

const char* IdleWaitName(IdleWait wait) { return wait == IdleWait::kSpin ? "spin" : "sleep"; }

}  // namespace hapsim::common
