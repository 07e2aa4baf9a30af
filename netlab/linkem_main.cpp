// hapsim-linkem: a user-space network link emulator between network
// namespaces. This kernel has no netem qdisc, so delay, jitter, loss and a
// bandwidth cap are applied here, to every IP packet: each namespace (an
// emulated host) has a TUN device, and this process forwards packets between
// them through per-host access links (hapsim/netlab/link_switch.h). DDS (UDP)
// and gRPC (TCP) cross the same link without knowing it. netlab/netlab.sh
// builds the namespaces and devices and starts this.
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hapsim/common/flags.h"
#include "hapsim/netlab/forwarder.h"
#include "hapsim/netlab/ip_packet.h"
#include "hapsim/netlab/tun.h"

namespace {

using hapsim::netlab::HostSpec;

constexpr const char* kSummary =
    "User-space link emulator of hapsim's network lab: forwards every IP packet between the TUN\n"
    "devices of several network namespaces (emulated hosts), each behind its own access link with\n"
    "a one-way delay, jitter, random and bursty loss, a bandwidth cap and scheduled outages. A packet\n"
    "from host A to host B crosses A's link, then B's; multicast and broadcast reach every other host.\n"
    "netlab/netlab.sh makes the namespaces and devices and runs this (docs/deploy.md).\n\n"
    "--host NETNS,ADDRESS[,KEY=VALUE...]  KEYs: delay_ms, jitter_ms (uniform ±), reorder (0/1), loss,\n"
    "    burst_rate, burst_packets (Gilbert-Elliott bursts), rate_mbit_s, queue_ms, outage=START_S+DURATION_S\n\n"
    "Exit: 0 ran for --seconds or until SIGINT/SIGTERM, 1 a device could not be opened or went away,\n"
    "2 bad flags. With --report, a JSON summary per host (packets sent, delivered, dropped by cause).";

std::atomic<bool> g_stop{false};
void OnSignal(int) { g_stop = true; }

// "NETNS,ADDRESS[,KEY=VALUE...]" -> a host; "" or what is wrong.
std::string ParseHost(const std::string& text, HostSpec* host) {
  const auto first = text.find(',');
  if (first == std::string::npos || first == 0) return "--host '" + text + "' must be NETNS,ADDRESS[,KEY=VALUE...]";
  host->name = text.substr(0, first);
  const auto second = text.find(',', first + 1);
  const std::string address =
      text.substr(first + 1, second == std::string::npos ? std::string::npos : second - first - 1);
  if (!hapsim::netlab::ParseIpv4(address.c_str(), &host->address)) {
    return "--host " + host->name + ": '" + address + "' is not an IPv4 address";
  }
  std::string error;
  const std::string link = second == std::string::npos ? "" : text.substr(second + 1);
  if (!hapsim::netlab::ParseLinkProfile(link, &host->link, &error)) return "--host " + host->name + ": " + error;
  return "";
}

nlohmann::json Report(const hapsim::netlab::LinkSwitch& link_switch, const hapsim::netlab::ForwarderResult& run) {
  nlohmann::json report;
  report["elapsed_s"] = run.elapsed_s;
  report["write_errors"] = run.write_errors;
  report["vanished_hosts"] = run.vanished_hosts;
  report["to_vanished_packets"] = run.to_vanished;
  report["lateness_us"] = {{"p50", run.lateness_s.p50 * 1e6},
                           {"p99", run.lateness_s.p99 * 1e6},
                           {"max", run.lateness_s.max * 1e6},
                           {"count", run.lateness_s.count}};
  for (std::size_t i = 0; i < link_switch.hosts().size(); ++i) {
    const auto& h = link_switch.hosts()[i];
    const auto& c = link_switch.counters(i);
    report["hosts"].push_back({{"netns", h.name},
                               {"link", hapsim::netlab::ToString(h.link)},
                               {"sent_packets", c.sent_packets},
                               {"sent_bytes", c.sent_bytes},
                               {"sent_multicast_packets", c.sent_multicast_packets},
                               {"received_packets", c.received_packets},
                               {"received_bytes", c.received_bytes},
                               {"dropped_lost", c.lost},
                               {"dropped_burst", c.burst},
                               {"dropped_queue", c.queue},
                               {"dropped_outage", c.outage},
                               {"unroutable", c.unroutable}});
  }
  return report;
}

// The forwarder's wake-ups are its accuracy: ask for 1 ns timer slack and,
// if allowed, a real-time priority (the harness runs as root).
void AskForPromptWakeups(bool realtime) {
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  if (!realtime) return;
  sched_param param{};
  param.sched_priority = 10;
  if (sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
    std::fprintf(stderr, "hapsim-linkem: no real-time priority (%s); delays may run late under load\n",
                 std::strerror(errno));
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> host_texts;
  std::string tun_name = "hl0", report_file, ready_file;
  double seconds = 600.0;
  int seed = 1;
  bool realtime = false;
  double spin_lead_us = 0.0;
  hapsim::common::Flags flags("hapsim-linkem", kSummary);
  flags.AddList("host", &host_texts, "an emulated host: NETNS,ADDRESS[,KEY=VALUE...] (at least two)");
  flags.Add("tun", &tun_name, "the TUN device's name in every host's namespace");
  flags.Add("seconds", &seconds, "stop after this long [s] (a lab never outlives its test)");
  flags.Add("seed", &seed, "seed of the loss and jitter draws (each link its own stream)");
  flags.Add("realtime", &realtime, "run at SCHED_FIFO priority 10 (fewer late packets on a busy machine)");
  flags.Add("spin-lead-us", &spin_lead_us,
            "poll without sleeping for this long before each packet is due [us] (0: sleep until due; "
            "an idle CPU may wake 0.1 ms or more late)");
  flags.Add("report", &report_file, "write a JSON summary here at exit");
  flags.Add("ready-file", &ready_file, "create this file once every device is open");
  std::string error;
  switch (flags.Parse(argc, argv, &error)) {
    case hapsim::common::Flags::Result::kHelp:
      std::printf("%s", flags.Help().c_str());
      return 0;
    case hapsim::common::Flags::Result::kVersion:
      std::printf("%s", flags.Version().c_str());
      return 0;
    case hapsim::common::Flags::Result::kError:
      std::fprintf(stderr, "hapsim-linkem: %s\n", error.c_str());
      return 2;
    case hapsim::common::Flags::Result::kOk:
      break;
  }
  error = hapsim::common::FirstFlagOutOfRange(
      {{seconds > 0.0 && seconds <= 86400.0, "--seconds", "(0, 86400]"},
       {spin_lead_us >= 0.0 && spin_lead_us <= 10000.0, "--spin-lead-us", "[0, 10000]"}});
  std::vector<HostSpec> hosts(host_texts.size());
  for (std::size_t i = 0; i < hosts.size() && error.empty(); ++i) error = ParseHost(host_texts[i], &hosts[i]);
  if (error.empty() && hosts.size() < 2) error = "at least two --host are needed";
  for (std::size_t i = 0; i < hosts.size() && error.empty(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (hosts[j].address == hosts[i].address)
        error = "hosts " + hosts[j].name + " and " + hosts[i].name + " share an address";
    }
  }
  if (!error.empty()) {
    std::fprintf(stderr, "hapsim-linkem: %s\n", error.c_str());
    return 2;
  }
  std::vector<int> fds;
  for (const HostSpec& host : hosts) {
    const int fd = hapsim::netlab::OpenTunInNamespace(host.name, tun_name, &error);
    if (fd < 0) {
      std::fprintf(stderr, "hapsim-linkem: %s\n", error.c_str());
      return 1;
    }
    fds.push_back(fd);
  }
  signal(SIGINT, OnSignal);
  signal(SIGTERM, OnSignal);
  AskForPromptWakeups(realtime);
  hapsim::netlab::LinkSwitch link_switch(hosts, static_cast<std::uint64_t>(seed), hapsim::netlab::MonotonicNs());
  if (!ready_file.empty()) std::ofstream(ready_file) << getpid() << "\n";
  const auto run =
      hapsim::netlab::RunForwarder(&link_switch, fds, seconds, g_stop, static_cast<std::int64_t>(spin_lead_us * 1e3));
  for (int fd : fds) close(fd);
  const nlohmann::json report = Report(link_switch, run);
  if (!report_file.empty()) std::ofstream(report_file) << report.dump(2) << "\n";
  std::fprintf(stderr, "hapsim-linkem: %.1f s, emulator lateness p50 %.1f / p99 %.1f us (%zu packets)\n", run.elapsed_s,
               run.lateness_s.p50 * 1e6, run.lateness_s.p99 * 1e6, run.lateness_s.count);
  if (!run.ok) {
    std::fprintf(stderr, "hapsim-linkem: %s\n", run.error.c_str());
    return 1;
  }
  return 0;
}
