#include "hapsim/common/thread_setup.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace hapsim::common {

void LowerThisThreadPriority(int nice) { (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice); }

void RunThisThreadOnlyWhenIdle() {
  sched_param param{};
  param.sched_priority = 0;
  if (pthread_setschedparam(pthread_self(), SCHED_IDLE, &param) != 0) LowerThisThreadPriority();
}

namespace {
void NamePthread(pthread_t thread, const char* name) {
  const std::string cut(name, std::min<std::size_t>(std::strlen(name), 15));  // the kernel's limit
  (void)pthread_setname_np(thread, cut.c_str());
}
}  // namespace

void NameThisThread(const char* name) { NamePthread(pthread_self(), name); }

void NameThread(std::thread& thread, const char* name) { NamePthread(thread.native_handle(), name); }

bool RunThisThreadAtRealtime(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

RealtimeResult RaiseThreadsNamed(std::initializer_list<const char*> names, int priority) {
  RealtimeResult result;
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", error)) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (!std::getline(comm, name)) continue;  // the thread ended meanwhile
    if (std::none_of(names.begin(), names.end(), [&](const char* n) { return name == n; })) continue;
    sched_param param{};
    param.sched_priority = priority;
    const auto tid = static_cast<pid_t>(std::stol(task.path().filename().string()));
    if (sched_setscheduler(tid, SCHED_FIFO, &param) == 0) {
      ++result.raised;
    } else {
      ++result.refused;
    }
  }
  return result;
}

}  // namespace hapsim::common
