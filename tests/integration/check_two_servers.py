"""Checks two_servers.sh: one bridge, two servers serving the same session
id on one domain. The bridge must follow one server and render only its
models; each server must warn of the other."""
import csv
import re
import sys

from checks import check, finish, read_text

work = sys.argv[1]
bridge = read_text(work, "bridge.out")
servers = {}
for name in ("a", "b"):
    log, out = read_text(work, f"{name}.log"), read_text(work, f"{name}.out")
    servers[name] = {
        "instance": re.search(r"server instance ([0-9a-f]{16})", log).group(1),
        "scene": re.search(r"session t1 \((\w+)\)", out).group(1),
        "written": int(re.search(r"force models written (\d+)", out).group(1)),
        "peak_N": float(re.search(r"peak tool force ([\d.]+) N", out).group(1)),
        "log": log,
    }

m = re.search(r"following server ([0-9a-f]{16}); models from another server dropped (\d+)", bridge)
check(m is not None, "the bridge says which server it follows")
if m is None:
    finish()
followed_instance, dropped = m.group(1), int(m.group(2))
followed = [n for n, s in servers.items() if s["instance"] == followed_instance]
check(len(followed) == 1, f"the bridge follows one of the two servers ({followed_instance})")
ours, other = servers[followed[0]], servers["b" if followed[0] == "a" else "a"]
print(f"following the {ours['scene']} server: it wrote {ours['written']} models, the {other['scene']} "
      f"server {other['written']}; the bridge dropped {dropped}")

received = int(re.search(r"force models received (\d+)", bridge).group(1))
check(received <= ours["written"], f"models rendered ({received}) <= the followed server's ({ours['written']})")
# A server writes models until its device's pose is 250 ms old (--pose-timeout-ms):
# ~250 of the other's were written after the bridge had gone.
reachable = other["written"] - 250
check(dropped >= 0.9 * reachable,
      f"the other server's models reached the bridge and were dropped: {dropped} >= 90 % of {reachable} "
      f"({other['written']} written, the last 250 ms after the bridge left)")
check(int(re.search(r"server switches (\d+)", bridge).group(1)) == 0, "no server switch while both talk")

# The force at the stylus is the followed scene's: its peak matches that
# server's own peak tool force (the 8 mm insertion gives 1.8 N on the tissue
# block, 1.0 N in the acupuncture scene).
peak = float(re.search(r"force peak ([\d.]+) N", bridge).group(1))
check(abs(peak - ours["peak_N"]) <= 0.05 * ours["peak_N"],
      f"bridge force peak {peak:.3f} N within 5 % of the followed server's {ours['peak_N']:.3f} N "
      f"(the other's: {other['peak_N']:.3f} N)")

# Interleaved models of two scenes would flip the contact state every tick.
with open(f"{work}/bridge.csv") as f:
    states = [int(r["model_state"]) for r in csv.DictReader(f) if r["watchdog"] != "no-model"]
changes = sum(1 for a, b in zip(states, states[1:]) if a != b)
check(len(states) > 2500, f"{len(states)} ticks rendered a model")
check(changes <= 10, f"the rendered contact state changed {changes} times in 3 s (one insertion: a few)")
if ours["scene"] == "tissue_block":
    check(2 not in states, "the tissue block's models never say punctured")

for name, s in servers.items():
    check(re.search(r"another server .* publishes force models for session 't1'", s["log"]) is not None,
          f"server {name} ({s['scene']}) warns of the other server in t1's partition")
check("also publishes force models" in read_text(work, "bridge.log"), "the bridge warns of the second server")
finish()
