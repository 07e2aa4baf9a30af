"""Checks passivity_under_delay.sh: no passivity violation left uncorrected
with the models 0-200 ms late, on three scenes, the physics age that delay;
the needle's rendered work <= 0 over each insertion with models 1000 ms late."""
import csv
import os
import re
import sys

from checks import check, finish, read_text

work = sys.argv[1]
scenes = {"t1": "tissue_block", "t2": "acupuncture", "t3": "cutting"}
print("delay_ms session scene models force_peak_N passivity_corrected bounded uncorrected model_age_p99_ms")
for delay in (0, 50, 100, 200):
    out = read_text(work, f"delay_{delay}.out")
    blocks = re.split(r"(?=bridge: device \S+, session )", out)[1:]
    check(len(blocks) == 3, f"{delay} ms: three devices reported")
    for block in blocks:
        session = re.search(r"session (\w+)", block).group(1)
        models = int(re.search(r"force models received (\d+)", block).group(1))
        peak = float(re.search(r"force peak ([\d.]+) N", block).group(1))
        corrected, bounded, uncorrected = map(
            int, re.search(r"passivity corrected (\d+) \(bounded (\d+), uncorrected (\d+)\)", block).groups())
        age = re.search(r"model age p50 [\d.]+ / p99 ([\d.]+)", block)
        print(f"{delay} {session} {scenes[session]} {models} {peak:.3f} {corrected} {bounded} {uncorrected} "
              f"{age.group(1) if age else '-'}")
        check(models > 1000, f"{delay} ms, {session}: models reached the device ({models})")
        check(uncorrected == 0, f"{delay} ms, {session}: no passivity violation left uncorrected ({uncorrected})")
        check(0.0 < peak <= 2.5, f"{delay} ms, {session}: the device was pressed, within the clamp ({peak:.3f} N)")
        # The models answer poses sensed one loopback round trip (< 1 ms) plus the delay before they arrive.
        physics = float(re.search(r"physics age p50 ([\d.]+)", block).group(1))
        check(delay <= physics <= delay + 2.0, f"{delay} ms, {session}: physics age p50 is the delay ({physics} ms)")

# Work on the hand per insertion cycle (from one "approach" to the next), from the trace:
# sum of F . dx with the force commanded at each tick; positive: the device gave energy.
with open(os.path.join(work, "needle_1000.csv")) as f:
    rows = list(csv.DictReader(f))
cycles, work_J = [], 0.0
for k in range(len(rows) - 1):
    if rows[k]["phase"] == "approach" and k > 0 and rows[k - 1]["phase"] != "approach":
        cycles.append(work_J)
        work_J = 0.0
    a, b = rows[k], rows[k + 1]
    work_J += sum(float(a[f"f{c}_N"]) * (float(b[f"{c}_m"]) - float(a[f"{c}_m"])) for c in "xyz")
peak = max(abs(float(r["fz_N"])) for r in rows)
print("needle, models 1000 ms late: rendered work per insertion (mJ):", [round(1e3 * w, 3) for w in cycles],
      f"peak {peak:.3f} N")
check(len(cycles) == 2, f"two whole insertions traced ({len(cycles)})")
# A second late, each layer's model arrives when the needle is already past where it gives
# (rendered as the tunnel it left) and the muscle's when it withdraws: small but real forces.
pushed = sum(1 for r in rows if abs(float(r["fz_N"])) > 0.01)
check(peak > 0.1 and pushed > 500, f"the needle felt the tissue ({peak:.3f} N peak, {pushed} ticks over 0.01 N)")
for i, w in enumerate(cycles):
    check(w <= 0.0, f"insertion {i + 1}: the rendering gave the hand no energy ({1e3 * w:.3f} mJ)")
finish()
