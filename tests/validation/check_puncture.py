#!/usr/bin/python3
"""Independent cross-check of `hapsim-validate puncture` output.

Rebuilds the acupuncture model from its specification only (Table 2 layers,
Table 1 damping with d in N*s/m per mm, hexagonal force net with zero-length
surface springs k_s = 30 K and zero-length virtual springs K, puncture when
ring w's mean deflection reaches 0.02 L) with numpy/scipy -- its own lattice,
its own dense solve -- and predicts the force at every tick of
force_depth.csv from the tip depth alone. Also checks springback.csv against
the shape-matching end state (rest shape lowered by the net's mean
deflection). Usage: check_puncture.py OUT_DIR  (exit 0 = all checks pass)
"""
import csv
import sys

import numpy as np
import scipy.linalg

TAU, ZETA = 30.0, 0.02            # k_s / K and ζ / L (scene defaults)
LAYERS = [  # name, thickness mm, K N/mm, d (N*s/m per mm), w, L mm
    ("skin", 0.8, 0.16, 3.0, 8, 2.0),
    ("fat", 8.4, 0.08, 1.0, 4, 1.0),
    ("muscle", 39.0, 0.23, 3.0, 10, 2.5),
]


def net(w, K):
    """Influence vector of the hex net: nodes at hex distance <= w-1."""
    nodes = [(q, r) for q in range(-w + 1, w) for r in range(-w + 1, w) if max(abs(q), abs(r), abs(q + r)) <= w - 1]
    ring = np.array([max(abs(q), abs(r), abs(q + r)) for q, r in nodes])
    idx = {n: i for i, n in enumerate(nodes)}
    n = len(nodes)
    A = K * np.eye(n)
    for (q, r), i in idx.items():
        for dq, dr in ((1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)):
            j = idx.get((q + dq, r + dr))
            if j is not None:  # each pair twice: add k_s/2 per visit
                A[i, i] += TAU * K / 2
                A[i, j] -= TAU * K / 2
                A[j, j] += TAU * K / 2
                A[j, i] -= TAU * K / 2
    c = idx[(0, 0)]
    free = [i for i in range(n) if i != c]
    g = np.zeros(n)
    g[c] = 1.0
    g[free] = scipy.linalg.solve(A[np.ix_(free, free)], -A[free, c])
    return g, ring


def main(out):
    ok = True
    rows = [r for r in csv.DictReader(open(f"{out}/force_depth.csv"))]
    t = np.array([float(r["t_s"]) for r in rows])
    depth_mm = np.array([float(r["depth_mm"]) for r in rows])
    force = np.array([float(r["force_N"]) for r in rows])
    turn = int(np.argmax(depth_mm))
    v = (depth_mm[turn] - depth_mm[turn - 200]) / (t[turn] - t[turn - 200]) * 1e-3  # m/s
    print(f"insertion speed from the CSV: {v * 1e3:.4f} mm/s")

    tops, stiff, z1s, top = [], [], [], 0.0
    for name, h, K, d, w, L in LAYERS:
        g, ring = net(w, K * 1e3)
        gw = g[ring == w - 1].mean()
        z1 = ZETA * L / gw  # mm
        tops.append(top)
        stiff.append(K * g.sum())  # N/mm
        z1s.append(z1)
        print(f"{name}: K sum(g) = {K * g.sum():.4f} N/mm, Z1* = {z1:.5f} mm, peak surface force {K * g.sum() * z1:.4f} N")
        top += h

    def shaft(dmm, n_layers):  # N*s/m: sum d h, d in N*s/m per mm, h in mm
        b, top = 0.0, 0.0
        for (_, h, _, d, _, _), _i in zip(LAYERS, range(n_layers)):
            b += d * min(max(dmm - top, 0.0), h)
            top += h
        return b

    def expected_inserting(dmm):
        for i in range(3):
            if dmm < tops[i]:
                return v * shaft(dmm, i)  # inside layer i-1 (or free for i = 0)
            if dmm - tops[i] < z1s[i]:
                return stiff[i] * (dmm - tops[i]) + v * shaft(dmm, i)  # pressing surface i
        return v * shaft(dmm, 3)

    ins = [k for k in range(turn + 1) if depth_mm[k] > 0]
    dev = max(abs(force[k] - expected_inserting(depth_mm[k])) for k in ins)
    good = dev < 2e-6
    ok &= good
    print(f"insertion: max |F - independent model| over {len(ins)} ticks = {dev:.2e} N  {'ok' if good else 'FAIL'}")
    wd = [k for k in range(turn + 1, len(rows)) if depth_mm[k] > 0]
    dev = max(abs(force[k] + v * shaft(depth_mm[k], 3)) for k in wd)
    good = dev < 1e-9
    ok &= good
    print(f"withdrawal: max |F + v sum(d h)| = {dev:.2e} N (shaft friction only)  {'ok' if good else 'FAIL'}")

    drops = [k for k in range(1, turn + 1) if force[k - 1] > 0.01 and force[k] < 0.5 * force[k - 1]]
    good = len(drops) == 3
    ok &= good
    print(f"force drops (punctures) during insertion: {len(drops)}  {'ok' if good else 'FAIL'}")
    for i, k in enumerate(drops[:3]):
        exp = tops[i] + z1s[i]
        good = exp - 1e-6 <= depth_mm[k] <= exp + 0.005 + 1e-6
        ok &= good
        print(f"  {LAYERS[i][0]} puncture at {depth_mm[k]:.4f} mm (top + Z1* = {exp:.4f} mm), peak {force[k - 1]:.4f} N  {'ok' if good else 'FAIL'}")
    skin_peak = force[drops[0] - 1] if drops else 0.0
    good = 0.1 < skin_peak < 2.0
    ok &= good
    print(f"skin peak {skin_peak:.3f} N within 0.1-2 N  {'ok' if good else 'FAIL'}")
    print(f"shaft friction per mm at {v * 1e3:.1f} mm/s: skin {LAYERS[0][3] * v:.4f}, fat {LAYERS[1][3] * v:.4f}, muscle {LAYERS[2][3] * v:.4f} N/mm")

    sb = [(float(r["t_s"]), float(r["offset_mm"])) for r in csv.DictReader(open(f"{out}/springback.csv"))]
    off = np.array([o for _, o in sb])
    g, ring = net(LAYERS[0][4], LAYERS[0][2] * 1e3)
    z1p = depth_mm[drops[0]] if drops else 0.0
    final_expected = z1p * (1.0 - g.mean())
    good = off[-1] > 0 and abs(off[-1] - final_expected) < 1e-3 * final_expected and np.all(np.diff(off) >= -1e-12)
    ok &= good
    print(f"springback: ends {off[-1]:.5f} mm above the reference line (expected Z1(1 - mean g) = {final_expected:.5f} mm), rising  {'ok' if good else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: check_puncture.py OUT_DIR")
    sys.exit(main(sys.argv[1]))
