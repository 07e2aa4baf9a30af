"""Checks netlab_multicast.sh: with multicast discovery (no peer list) each
bridge found the server and felt its session's tissue, the processes exited
0, and multicast carried discovery only — the 1 kHz data went unicast."""
import json
import os
import re
import sys

from checks import check, exit_code, finish, read_text

work = sys.argv[1]
for name in ("server", "t1", "t2"):
    check(exit_code(work, name) == 0, f"{name} exits 0 (got {exit_code(work, name)})")
for t in ("t1", "t2"):
    out = read_text(work, f"{t}.out")
    received = re.search(r"force models received (\d+)", out)
    first = re.search(r"first force model ([\d.]+) s", out)
    peak = re.search(r"force peak ([\d.]+) N", out)
    check(received is not None and int(received.group(1)) > 20,
          f"{t}: found the server by multicast discovery ({received.group(0) if received else 'no models'})")
    check(first is not None and float(first.group(1)) < 1.5,
          f"{t}: first force model within 1.5 s ({first.group(1) if first else 'none'} s)")
    check(peak is not None and float(peak.group(1)) > 0.3, f"{t}: pressed into its tissue ({peak.group(0) if peak else '-'})")
with open(os.path.join(work, "link.json")) as f:
    hosts = {h["netns"].rsplit("-", 1)[1]: h for h in json.load(f)["hosts"]}
for name, h in hosts.items():
    check(h["sent_multicast_packets"] > 0, f"{name}: announced itself by multicast ({h['sent_multicast_packets']} packets)")
    # SPDP announces each participant about once a second (more at start); the data is unicast.
    unicast = h["sent_packets"] - h["sent_multicast_packets"]
    check(h["sent_multicast_packets"] <= 50 and unicast >= 100,
          f"{name}: multicast is discovery only ({h['sent_multicast_packets']} multicast, {unicast} unicast packets)")
finish()
