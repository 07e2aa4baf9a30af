#include "hapsim/common/thread_setup.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace hapsim::common {

void LowerThisThreadPriority(int nice) { (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice); }

void RunThisThreadOnlyWhenIdle() {
  sched_param param{};
  param.sched_priority = 0;
  if (pthread_setschedparam(pthread_self(), SCHED_IDLE, &param) != 0) LowerThisThreadPriority();
}

void NameThisThread(const char* name) {
  const std::string cut(name, std::min<std::size_t>(std::strlen(name), 15));
  (void)pthread_setname_np(pthread_self(), cut.c_str());
}

}  // namespace hapsim::common
