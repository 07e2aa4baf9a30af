"""Checks acupuncture_e2e.sh's outputs (standard library only).

Layer tops below the skin surface (z = 0): skin 0, fat 0.8 mm, muscle 9.2 mm
(paper Table 2). Each layer is pressed millimetres deep before it gives way
(the nonlinear force net); the expected depths are the model's own.
"""
import csv
import re
import sys

from checks import check, finish

work = sys.argv[1]


viewer = open(f"{work}/viewer.out").read()
m = re.search(r"punctures \(layer@tip depth below z=0\): (.*)", viewer)
check(m is not None, "the viewer's frames carried puncture events")
punctures = [(p.split("@")[0], float(p.split("@")[1].rstrip("mm"))) for p in m.group(1).split()] if m else []
check([p[0] for p in punctures] == ["skin", "fat", "muscle"],
      f"three punctures in order skin -> fat -> muscle (got {punctures})")
# The model's own puncture depths (hapsim-validate puncture, punctures.csv
# expected_depth_mm; checked there against an independent solve): skin
# 2.589 mm, fat 1.117 mm below where the skin gave way (along the fat's
# normal at the site), muscle 2.871 mm below its top at 9.2 mm (likewise).
# The window adds what the network can: poses a few ticks late or coalesced
# (10 ticks of 5 µm).
expected_mm = {"skin": 2.589, "fat": 3.707, "muscle": 12.071}
for layer, depth in punctures:
    if layer in expected_mm:
        check(expected_mm[layer] - 0.01 <= depth <= expected_mm[layer] + 0.05,
              f"{layer} punctured at {depth:.3f} mm (model: {expected_mm[layer]:.3f} mm, window -0.01/+0.05 mm)")

# Bridge force trace: the force the local model asks for drops sharply at
# each puncture (the layer's surface force is gone; only shaft friction and
# the next surface remain). A drop: from over 0.1 N (every layer's puncture
# force is 0.2 N or more) to under half within 5 ticks.
rows = list(csv.DictReader(open(f"{work}/trace.csv")))
force = lambda r: (float(r["req_fx_N"]) ** 2 + float(r["req_fy_N"]) ** 2 + float(r["req_fz_N"]) ** 2) ** 0.5
drops = []  # (t, depth_mm, before_N, after_N)
for i in range(5, len(rows)):
    before, after = force(rows[i - 5]), force(rows[i])
    if rows[i]["phase"] == "press" and before > 0.1 and after < 0.5 * before:
        t = float(rows[i]["t_s"])
        if not drops or t - drops[-1][0] > 0.02:
            drops.append((t, -float(rows[i]["z_m"]) * 1e3, before, after))
        else:  # same drop, keep the largest pre-drop force
            drops[-1] = (drops[-1][0], drops[-1][1], max(drops[-1][2], before), after)
for d in drops:
    print(f"     force drop at {d[1]:.2f} mm: {d[2]:.3f} N -> {d[3]:.3f} N")
check(len(drops) == 3, f"three force drops in the bridge's trace while inserting (got {len(drops)})")
if len(drops) == 3 and len(punctures) == 3:
    for (layer, depth), d in zip(punctures, drops):
        check(abs(depth - d[1]) < 0.05,
              f"{layer}: trace drop at {d[1]:.3f} mm matches the viewer's puncture at {depth:.3f} mm (within 0.05 mm)")
    check(0.1 <= drops[0][2] <= 2.0, f"skin puncture force {drops[0][2]:.3f} N within the measured 0.1-2 N")
    check(all(d[2] < 2.5 for d in drops), f"every puncture peak below the 2.5 N clamp ({[round(d[2], 3) for d in drops]} N)")
# Withdrawal: shaft friction only — axial, opposing the outward motion
# (pointing into the tissue, -z), shrinking as less shaft is inside, and
# zero once the tip is out. The scene's default stick-slip friction turns
# over while the tip crosses the stick band after the reversal (2 x Coulomb
# level / 300 N/m; the documented defaults, docs/validation.md: skin 10,
# fat 5, muscle 15 N per m inserted, layers 0.8 / 8.4 / 39 mm): the checks
# start past it.
def coulomb_N(depth_m):
    total, top = 0.0, 0.0
    for per_m, thick_m in ((10.0, 0.8e-3), (5.0, 8.4e-3), (15.0, 39e-3)):
        total += per_m * min(max(depth_m - top, 0.0), thick_m)
        top += thick_m
    return total


withdraw = [r for r in rows if r["phase"] == "withdraw"]
turn_z = min((float(r["z_m"]) for r in withdraw), default=0.0)
stick_band_m = 2.0 * coulomb_N(-turn_z) / 300.0
inside = [r for r in withdraw if float(r["z_m"]) < -1e-3 and float(r["z_m"]) > turn_z + stick_band_m]
lateral = max((abs(float(r["req_fx_N"])) + abs(float(r["req_fy_N"])) for r in inside), default=1.0)
check(bool(inside) and lateral < 1e-6, f"withdrawal force is axial (max lateral {lateral:.1e} N)")
check(all(float(r["req_fz_N"]) <= 0.0 for r in inside), "withdrawal force opposes the outward motion")
samples = inside[20::100]  # skip the first ticks while the model catches up with the reversal
shrinking = all(force(b) <= force(a) + 1e-3 for a, b in zip(samples, samples[1:]))
check(len(samples) > 5 and shrinking, "withdrawal force shrinks as the needle comes out")
outside = [force(r) for r in rows if r["phase"] == "withdraw" and float(r["z_m"]) > 0.5e-3]
check(bool(outside) and max(outside) < 1e-6, f"no force once the tip is out (max {max(outside, default=1):.1e} N)")
finish()
