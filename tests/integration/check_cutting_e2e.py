"""Checks cutting_e2e.sh's outputs (standard library only).

The stroke: entry at x = -6 mm, y = 0, 12 mm along +x at 5 mm/s, 1.5 mm
deep; the scene commits the incision in 1.6 mm segments of blade travel
(cutting scene defaults), so the incision is 12 mm less under one segment.
"""
import csv
import math
import re
import sys
from collections import Counter

from checks import check, finish, read_text

work = sys.argv[1]
STROKE_MM, SEGMENT_MM, ENTRY_X_MM, SPEED_M_PER_S = 12.0, 1.6, -6.0, 0.005
# The drag law the force model carries (defaults: cut_force_N 0.3,
# cut_damping_Ns_per_m 5, smoothing speed 2 mm/s): F = F_c tanh(v/v_s) + c v.
DRAG_N = 0.3 * math.tanh(SPEED_M_PER_S / 0.002) + 5.0 * SPEED_M_PER_S


def viewer_stats(name):
    text = read_text(work, f"{name}.out")
    m = re.search(r"frames (\d+) \(keyframes (\d+), deltas (\d+)\).*gaps (\d+), topology mismatches (\d+), "
                  r"malformed (\d+), resubscribes (\d+)", text)
    events = dict(e.split("=") for e in re.search(r"events:(.*)", text).group(1).split()) if "events:" in text else {}
    cut = re.search(r"frames with topology edits (\d+), incisions:(.*)", text)
    incisions = [float(x.rstrip("mm")) for x in cut.group(2).split()] if cut and "none" not in cut.group(2) else []
    return m, events, int(cut.group(1)) if cut else 0, incisions


for name in ("early", "late"):
    m, events, topo_frames, incisions = viewer_stats(name)
    check(m is not None, f"{name} viewer printed its frame counts")
    if not m:
        continue
    frames, keyframes, deltas, gaps, mismatches, malformed, resubscribes = map(int, m.groups())
    check(keyframes == 1 and resubscribes == 0,
          f"{name} viewer: one keyframe, then deltas only through the cut (keyframes {keyframes}, deltas {deltas}, "
          f"resubscribes {resubscribes})")
    check(gaps == 0 and mismatches == 0 and malformed == 0,
          f"{name} viewer: no gap, topology mismatch or malformed frame ({gaps}, {mismatches}, {malformed})")
    # The early viewer saw every segment arrive as topology edits; the late
    # one (joined mid-stroke) at least the rest of them.
    least = int((STROKE_MM - SEGMENT_MM) / SEGMENT_MM) if name == "early" else 1
    check(topo_frames >= least, f"{name} viewer: {topo_frames} frames carried topology edits (>= {least})")
    check(events.get("cut_end") == "1" and (name == "late" or events.get("cut_start") == "1"),
          f"{name} viewer: cut events {({k: v for k, v in events.items() if k.startswith('cut')})}")
    check(len(incisions) == 1 and STROKE_MM - SEGMENT_MM < incisions[0] <= STROKE_MM + 1e-6,
          f"{name} viewer: incision length {incisions} mm, within one segment under the {STROKE_MM} mm stroke")


def read_obj(name):
    vertices, parts, part = [], {}, None
    for line in open(f"{work}/{name}.obj"):
        f = line.split()
        if not f:
            continue
        if f[0] == "v":
            vertices.append(tuple(1e3 * float(c) for c in f[1:4]))  # mm
        elif f[0] == "o":
            part = f[1]
            parts.setdefault(part, [])
        elif f[0] == "f":
            parts[part].append(tuple(int(i) - 1 for i in f[1:4]))
    return vertices, parts


early_v, early_p = read_obj("early")
late_v, late_p = read_obj("late")
check(set(early_p) == {"skin", "wound", "blade"} and len(early_p["wound"]) > 0,
      f"the viewer's mesh has skin, wound and blade parts ({ {k: len(v) for k, v in early_p.items()} } triangles)")
check(early_p == late_p and len(early_v) == len(late_v),
      "both viewers end with the same triangles (one joined mid-cut from a keyframe)")
if len(early_v) == len(late_v):
    worst = max(math.dist(a, b) for a, b in zip(early_v, late_v))
    # Their last frames are up to a frame period apart while the wound settles.
    check(worst < 0.05, f"and the same vertex positions within 0.05 mm (worst {worst:.4f} mm)")

# The wound: edges of the skin used by one triangle, away from the patch's
# border (60 x 40 mm), are the incision's lips: two of them, each about the
# incision long, and open in the middle (lips apart in y).
tissue = early_p.get("skin", []) + early_p.get("wound", [])
edges = Counter()
for a, b, c in tissue:
    for u, v in ((a, b), (b, c), (c, a)):
        edges[(min(u, v), max(u, v))] += 1
interior = lambda i: abs(early_v[i][0]) < 29.0 and abs(early_v[i][1]) < 19.0
lips = [e for e, n in edges.items() if n == 1 and interior(e[0]) and interior(e[1])]
lip_length = sum(math.dist(early_v[a][:2], early_v[b][:2]) for a, b in lips)
incision = viewer_stats("early")[3]
if incision:
    check(2 * (incision[0] - 1.0) < lip_length < 2 * (incision[0] + 2.0),
          f"the wound's two lips total {lip_length:.2f} mm for a {incision[0]:.2f} mm incision")
lip_nodes = {i for e in lips for i in e}
middle = [early_v[i] for i in lip_nodes if abs(early_v[i][0] - (ENTRY_X_MM + 0.5 * STROKE_MM)) < 2.0]
upper = [p[1] for p in middle if p[1] > 0.0]
lower = [p[1] for p in middle if p[1] < 0.0]
gape = min(upper) - max(lower) if upper and lower else 0.0
check(gape > 0.05, f"the wound gapes in the middle of the incision: lips {gape:.3f} mm apart")

# The device's force model: nothing in the air; while cutting, a drag
# against the stroke (+x) close to the law's value, little sideways.
rows = list(csv.DictReader(open(f"{work}/trace.csv")))
air = [r for r in rows if r["phase"] == "approach"]
check(bool(air) and max(abs(float(r[k])) for r in air for k in ("req_fx_N", "req_fy_N", "req_fz_N")) == 0.0,
      "no force in the air (approach)")
cutting = [r for r in rows if r["phase"] == "cut"][100:]  # after the blade is up to speed in the skin
drag = sorted(-float(r["req_fx_N"]) for r in cutting)
median = drag[len(drag) // 2] if drag else 0.0
# The blade's sides push the lips across the incision only (its edge parts
# the skin; the law is that resistance), so along a straight stroke the drag
# is the law; 2 %: the stroke's speed wavers with the device's clock.
check(abs(median - DRAG_N) <= 0.02 * DRAG_N,
      f"drag while cutting: median {median:.4f} N against the stroke; the law gives {DRAG_N:.4f} N")
# Depth is felt while cutting: the pressing law from the rest surface,
# k (0 - z) with k = contact_stiffness_N_per_m 300 (the blade moves
# level, so its damping adds nothing); the blade's tilted sides take a little
# off (seen -4 %).
normal = sorted(float(r["req_fz_N"]) / (300.0 * -float(r["z_m"])) for r in cutting if float(r["z_m"]) < 0.0)
normal_median = normal[len(normal) // 2] if normal else 0.0
check(0.9 < normal_median <= 1.0,
      f"vertical force while cutting: median {normal_median:.3f} x the pressing law k (0 - z) at the blade's depth")
sideways = max((abs(float(r["req_fy_N"])) for r in cutting), default=1.0)
check(sideways < 0.5 * median, f"little sideways force while cutting straight (max {sideways:.3f} N)")
finish()
