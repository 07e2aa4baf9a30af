"""Summarises msm_rounds.sh's JSON files (standard library only).

For each mesh size: the median over rounds of each round's median
springs_per_s, for the default kernel, the portable kernel and (if present,
files old*.json) a previous build; the slowest round of the default kernel;
and the median over rounds of the same-run triad rate and of the step's
fraction of it.
"""
import collections
import glob
import json
import statistics
import sys

folder = sys.argv[1]


def load(prefix):
    rows = collections.defaultdict(list)  # (benchmark, grid) -> [round medians]
    for path in sorted(glob.glob(f"{folder}/{prefix}*.json")):
        for b in json.load(open(path))["benchmarks"]:
            if b.get("aggregate_name") != "median":
                continue
            _, name, grid = b["run_name"].split("/")
            rows[(name, int(grid.split(":")[1]))].append(b)
    return rows


new, old = load("new"), load("old")
rate = lambda bs: statistics.median(b["springs_per_s"] for b in bs)
print(f"rounds: {len(glob.glob(folder + '/new*.json'))}\n")
print("| springs | working set | previous binary | portable kernel | default kernel | default / portable "
      "| default, slowest round | default step time | triad | fraction of triad |")
print("|---|---|---|---|---|---|---|---|---|---|")
for grid in sorted({g for (_, g) in new}):
    d, p = new[("symplectic_euler", grid)], new[("symplectic_euler_portable", grid)]
    o = old.get(("symplectic_euler", grid))
    springs = d[0]["springs"]
    triad = statistics.median(b["triad_GBps"] for b in d)
    fraction = statistics.median(b["step_GBps"] / b["triad_GBps"] for b in d)
    previous = f"{rate(o) / 1e6:.0f} M/s" if o else "-"
    print(f"| {int(springs):,} | {d[0]['working_set_MB']:.1f} MB | {previous} | {rate(p) / 1e6:.0f} M/s "
          f"| **{rate(d) / 1e6:.0f} M/s** | {rate(d) / rate(p):.2f}x "
          f"| {min(b['springs_per_s'] for b in d) / 1e6:.0f} M/s | {springs / rate(d) * 1e3:.3f} ms "
          f"| {triad:.0f} GB/s | {fraction:.2f} |")
