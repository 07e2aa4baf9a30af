// The threads of the test process, by name and kernel thread id: what the
// tests of thread placement and scheduling look at (/proc/self/task).
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hapsim::test {

struct ProcessThread {
  std::string name;
  pid_t tid = 0;
};

inline std::vector<ProcessThread> ThreadsOfThisProcess() {
  std::vector<ProcessThread> threads;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (!std::getline(comm, name)) continue;  // the thread ended meanwhile
    threads.push_back({name, static_cast<pid_t>(std::stol(task.path().filename().string()))});
  }
  return threads;
}

}  // namespace hapsim::test
