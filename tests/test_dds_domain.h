// A DDS domain id no other test process on this machine is using. ctest
// runs test processes in parallel, and two servers on one domain see each
// other's sessions and devices, so each process claims its own: the first
// free id in [kFirstTestDomain, kFirstTestDomain + kTestDomains), free
// meaning nobody holds an exclusive lock on /tmp/hapsim-test-domain-ID.lock.
// The lock is held until the process exits (its descriptor is never
// closed). The shell tests (tests/integration/lib.sh) claim through the
// same files, so C++ and shell tests never share a domain either.
#pragma once
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdint>
#include <string>

namespace hapsim::test {

inline constexpr std::uint32_t kFirstTestDomain = 20;
inline constexpr std::uint32_t kTestDomains = 200;  // 20..219 (Cyclone takes 0..232)

inline std::uint32_t ClaimTestDdsDomain() {
  // Start where this process's id points, so parallel processes rarely try the same files.
  const auto start = static_cast<std::uint32_t>(::getpid()) % kTestDomains;
  for (std::uint32_t i = 0; i < kTestDomains; ++i) {
    const std::uint32_t domain = kFirstTestDomain + (start + i) % kTestDomains;
    const std::string path = "/tmp/hapsim-test-domain-" + std::to_string(domain) + ".lock";
    const int fd = ::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return domain;  // held until exit
    ::close(fd);
  }
  return kFirstTestDomain + start;  // all 200 taken: share one, as before
}

}  // namespace hapsim::test
