#include "hapsim/netlab/tun.h"

#include <fcntl.h>
#include <linux/if.h>
#include <linux/if_tun.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hapsim::netlab {
namespace {

std::string Errno(const std::string& what) { return what + ": " + std::strerror(errno); }

// Closes a descriptor when leaving scope.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) close(fd);
  }
};

int AttachTun(const std::string& ifname, std::string* error) {
  const int fd = open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    *error = Errno("cannot open /dev/net/tun");
    return -1;
  }
  ifreq request{};
  request.ifr_flags = IFF_TUN | IFF_NO_PI;
  std::strncpy(request.ifr_name, ifname.c_str(), IFNAMSIZ - 1);
  if (ioctl(fd, TUNSETIFF, &request) < 0) {
    *error = Errno("cannot attach to TUN device " + ifname);
    close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

int OpenTunInNamespace(const std::string& netns, const std::string& ifname, std::string* error) {
  if (ifname.empty() || ifname.size() >= IFNAMSIZ) {
    *error = "TUN device name '" + ifname + "' must have 1 to 15 characters";
    return -1;
  }
  if (netns.empty()) return AttachTun(ifname, error);
  Fd own{open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC)};
  if (own.fd < 0) {
    *error = Errno("cannot open this process's network namespace");
    return -1;
  }
  Fd target{open(("/var/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC)};
  if (target.fd < 0) {
    *error = Errno("cannot open network namespace " + netns + " (/var/run/netns/" + netns + ")");
    return -1;
  }
  if (setns(target.fd, CLONE_NEWNET) < 0) {
    *error = Errno("cannot enter network namespace " + netns);
    return -1;
  }
  const int fd = AttachTun(ifname, error);
  if (setns(own.fd, CLONE_NEWNET) < 0) {
    // Staying in a host's namespace would open the next host's device there.
    *error = Errno("cannot return from network namespace " + netns);
    if (fd >= 0) close(fd);
    return -1;
  }
  if (fd < 0) *error += " in namespace " + netns;
  return fd;
}

}  // namespace hapsim::netlab
