"""Checks acupuncture_e2e.sh's outputs (standard library only).

Layer tops below the skin surface (z = 0): skin 0, fat 0.8 mm, muscle 9.2 mm
(paper Table 2). A puncture happens once the layer's surface has been pushed
in, so each puncture depth lies below its layer's top.
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
tops_mm = {"skin": 0.0, "fat": 0.8, "muscle": 9.2}
next_tops_mm = {"skin": 0.8, "fat": 9.2, "muscle": 48.2}
for layer, depth in punctures:
    if layer in tops_mm:
        # Below the layer's own top, and above the next layer's top plus a
        # generous dimple allowance (the layer below is pushed too).
        check(tops_mm[layer] < depth < next_tops_mm[layer] + 5.0,
              f"{layer} punctured at {depth:.2f} mm, below its top at {tops_mm[layer]} mm")

# Bridge force trace: the force the local model asks for drops sharply at
# each puncture (the layer's surface force is gone; only shaft friction and
# the next surface remain). A drop: from over 0.02 N (the fat's peak is only
# ~0.066 N at 2.5 mm/s; shaft friction before it is ~0.006 N) to under half
# within 5 ticks.
rows = list(csv.DictReader(open(f"{work}/trace.csv")))
force = lambda r: (float(r["req_fx_N"]) ** 2 + float(r["req_fy_N"]) ** 2 + float(r["req_fz_N"]) ** 2) ** 0.5
drops = []  # (t, depth_mm, before_N, after_N)
for i in range(5, len(rows)):
    before, after = force(rows[i - 5]), force(rows[i])
    if rows[i]["phase"] == "press" and before > 0.02 and after < 0.5 * before:
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
        check(abs(depth - d[1]) < 1.0,
              f"{layer}: trace drop at {d[1]:.2f} mm matches the viewer's puncture at {depth:.2f} mm (within 1 mm)")
    check(0.1 <= drops[0][2] <= 2.0, f"skin puncture force {drops[0][2]:.3f} N within the measured 0.1-2 N")
# Withdrawal: shaft friction only — axial, opposing the outward motion
# (pointing into the tissue, -z), shrinking as less shaft is inside, and
# zero once the tip is out. The scene's default stick-slip friction turns
# over while the tip crosses the stick band after the reversal (2 x Coulomb
# level / 300 N/m, < 0.3 mm at 30 mm depth): the checks start past it.
withdraw = [r for r in rows if r["phase"] == "withdraw"]
turn_z = min((float(r["z_m"]) for r in withdraw), default=0.0)
inside = [r for r in withdraw if float(r["z_m"]) < -1e-3 and float(r["z_m"]) > turn_z + 0.3e-3]
lateral = max((abs(float(r["req_fx_N"])) + abs(float(r["req_fy_N"])) for r in inside), default=1.0)
check(bool(inside) and lateral < 1e-6, f"withdrawal force is axial (max lateral {lateral:.1e} N)")
check(all(float(r["req_fz_N"]) <= 0.0 for r in inside), "withdrawal force opposes the outward motion")
samples = inside[20::100]  # skip the first ticks while the model catches up with the reversal
shrinking = all(force(b) <= force(a) + 1e-3 for a, b in zip(samples, samples[1:]))
check(len(samples) > 5 and shrinking, "withdrawal force shrinks as the needle comes out")
outside = [force(r) for r in rows if r["phase"] == "withdraw" and float(r["z_m"]) > 0.5e-3]
check(bool(outside) and max(outside) < 1e-6, f"no force once the tip is out (max {max(outside, default=1):.1e} N)")
finish()
