#include "hapsim/common/thread_setup.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace hapsim::common {

void LowerThisThreadPriority(int nice) { (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice); }

void RunThisThreadOnlyWhenIdle() {
  sched_param param{};
  param.sched_priority = 0;
  if (pthread_setschedparam(pthread_self(), SCHED_IDLE, &param) != 0) LowerThisThreadPriority();
}

void RunThreadInBatch(std::thread& thread) {
  sched_param param{};
  param.sched_priority = 0;
  (void)pthread_setschedparam(thread.native_handle(), SCHED_BATCH, &param);
}

namespace {
void NamePthread(pthread_t thread, const char* name) {
  const std::string cut(name, std::min<std::size_t>(std::strlen(name), 15));  // the kernel's limit
  (void)pthread_setname_np(thread, cut.c_str());
}

cpu_set_t CpusOfThisThread() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) CPU_ZERO(&set);
  return set;
}

template <class Visit>
void ForEachThreadOfThisProcess(Visit visit) {
  std::error_code error;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", error)) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (!std::getline(comm, name)) continue;  // the thread ended meanwhile
    visit(static_cast<pid_t>(std::stol(task.path().filename().string())), name);
  }
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
  return RaiseThreadsWhere(
      [&](const std::string& name) {
        return std::any_of(names.begin(), names.end(), [&](const char* n) { return name == n; });
      },
      priority);
}

RealtimeResult RaiseThreadsWhere(const std::function<bool(const std::string& name)>& chosen, int priority) {
  RealtimeResult result;
  ForEachThreadOfThisProcess([&](pid_t tid, const std::string& name) {
    if (!chosen(name)) return;
    sched_param param{};
    param.sched_priority = priority;
    ++(sched_setscheduler(tid, SCHED_FIFO, &param) == 0 ? result.raised : result.refused);
  });
  return result;
}

std::string CheckTickCpus(const std::vector<int>& tick_cpus) {
  if (tick_cpus.empty()) return "no CPU given";
  const cpu_set_t allowed = CpusOfThisThread();
  for (const int cpu : tick_cpus) {
    if (cpu < 0 || cpu >= CPU_SETSIZE || !CPU_ISSET(cpu, &allowed)) {
      return "CPU " + std::to_string(cpu) + " is not one this process may run on";
    }
  }
  if (CPU_COUNT(&allowed) <= static_cast<int>(tick_cpus.size())) {
    return "no CPU would be left for the other threads (this process may run on " +
           std::to_string(CPU_COUNT(&allowed)) + ")";
  }
  return "";
}

AffinityResult SplitThreadsByCpu(const std::function<bool(const std::string& name)>& on_tick_path,
                                 const std::vector<int>& tick_cpus) {
  cpu_set_t rest = CpusOfThisThread();
  cpu_set_t tick;
  CPU_ZERO(&tick);
  for (const int cpu : tick_cpus) {
    CPU_SET(cpu, &tick);
    CPU_CLR(cpu, &rest);
  }
  AffinityResult result;
  ForEachThreadOfThisProcess([&](pid_t tid, const std::string& name) {
    const bool tick_path = on_tick_path(name);
    if (sched_setaffinity(tid, sizeof(cpu_set_t), tick_path ? &tick : &rest) != 0) {
      ++result.refused;
    } else {
      ++(tick_path ? result.tick_path : result.others);
    }
  });
  return result;
}

std::vector<int> CpusOfThread(int tid) {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(tid, sizeof set, &set) != 0) return cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &set)) cpus.push_back(cpu);
  }
  return cpus;
}

std::optional<std::vector<int>> ParseCpuList(const std::string& text) {
  std::set<int> cpus;
  std::stringstream items(text);
  std::string item;
  const auto number = [](const std::string& digits, int* out) {
    if (digits.empty() || digits.size() > 4 || digits.find_first_not_of("0123456789") != std::string::npos)
      return false;
    *out = std::atoi(digits.c_str());
    return *out < CPU_SETSIZE;
  };
  while (std::getline(items, item, ',')) {
    const auto dash = item.find('-');
    int first = 0, last = 0;
    if (dash == std::string::npos) {
      if (!number(item, &first)) return std::nullopt;
      last = first;
    } else if (!number(item.substr(0, dash), &first) || !number(item.substr(dash + 1), &last) || last < first) {
      return std::nullopt;
    }
    for (int cpu = first; cpu <= last; ++cpu) cpus.insert(cpu);
  }
  if (cpus.empty() || (!text.empty() && text.back() == ',')) return std::nullopt;
  return std::vector<int>(cpus.begin(), cpus.end());
}

}  // namespace hapsim::common
