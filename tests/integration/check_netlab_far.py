"""Checks netlab_far.sh's run: 100 ms round trip seen by the watchdog, a far
viewer at full rate, bounded shutdowns when a network interface vanishes."""
import json
import os
import re
import sys

from checks import check, finish, read_text

work = sys.argv[1]

for name in ("far", "viewer"):
    check(read_text(work, f"{name}.rc").strip() == "0", f"{name} exited 0")

# The far bridge: 50 ms each way. Its physics age is the round trip (plus the
# gap since the model arrived, under 1 ms at 1 kHz, and the emulator's ~0.1 ms).
out = read_text(work, "far.out")
rtt = float(re.search(r"round trip p50 ([\d.]+)", out).group(1))
age50, age99 = map(float, re.search(r"physics age p50 ([\d.]+) / p99 ([\d.]+)", out).groups())
gap99 = float(re.search(r"model age p50 [\d.]+ / p99 ([\d.]+)", out).group(1))
check(100.0 <= rtt <= 102.0, f"round trip p50 within [100, 102] ms ({rtt})")
check(rtt <= age50 <= rtt + 1.5, f"physics age p50 is the round trip plus under 1.5 ms ({age50} vs {rtt})")
check(age99 <= rtt + 5.0, f"physics age p99 within 5 ms of the round trip ({age99})")
check(gap99 <= 5.0, f"stream gap p99 stays small: the stream itself is fine ({gap99} ms)")
warnings, fades, delay_warnings = map(
    int, re.search(r"warnings (\d+), fades (\d+), delay warnings (\d+)", out).groups())
disarms = int(re.search(r"disarms (\d+)", out).group(1))
check(delay_warnings >= 1, f"the watchdog warned of the felt lag ({delay_warnings} delay warnings)")
check(fades == 0 and disarms == 0, f"100 ms of lag neither fades nor disarms the force (fades {fades}, disarms {disarms})")
# Until its first model the stylus is free: discovery (SPDP, then SEDP: 2-3 round trips) and the
# first pose's answer (one more), so a few round trips; 6 (0.6 s) at most.
first = float(re.search(r"first force model ([\d.]+) s", out).group(1))
check(first <= 0.6, f"first force within 6 round trips of the bridge's start ({first} s)")
peak = float(re.search(r"pressing ([\d.]+) N", out).group(1))
# The tissue block's physics at 5 mm is ~0.94 N (integration.openhaptics_chain, on loopback).
check(0.9 <= peak <= 1.3, f"the force is rendered, not faded: peak at 5 mm within [0.9, 1.3] N ({peak} N)")

# The far viewer: 60 Hz snapshots across 100 ms of round trip.
v = read_text(work, "viewer.out")
frames = int(re.search(r"frames (\d+)", v).group(1))
malformed = int(re.search(r"malformed (\d+)", v).group(1))
check(frames >= 300, f"far viewer: >= 50 frames/s over 6 s ({frames} frames)")
check(malformed == 0, f"far viewer: no malformed frames ({malformed})")

# Interfaces that vanished: SIGTERM still ends the process, in a bounded time, without a log flood.
for name, limit_ms, code in (("lost", 3000 + 1500, 0), ("server", 5000 + 1500, 0)):
    rc, elapsed_ms = map(int, read_text(work, f"{name}.stop").split())
    log = read_text(work, f"{name}.log")
    lines = log.count("\n")
    check(rc == code, f"{name} without its interface exits {code} on SIGTERM (exit {rc})")
    check(elapsed_ms <= limit_ms, f"{name} without its interface stops within {limit_ms} ms ({elapsed_ms} ms)")
    check(lines <= 100, f"{name}'s log is not flooded by failed sends ({lines} lines)")
# Multicast on the LAN config: discovery only (a few SPDP announcements per host), never the 1 kHz data.
with open(os.path.join(work, "link.json")) as f:
    hosts = {h["netns"].rsplit("-", 1)[1]: h for h in json.load(f)["hosts"]}
for name, h in hosts.items():
    share = h["sent_multicast_packets"] / max(1, h["sent_packets"])
    check(h["sent_multicast_packets"] <= 50 and share <= 0.01,
          f"{name}: multicast is discovery only ({h['sent_multicast_packets']} of {h['sent_packets']} packets)")

lost_out = read_text(work, "lost.out")
check("force peak" in lost_out, "the lost bridge printed its report before teardown")

finish()
