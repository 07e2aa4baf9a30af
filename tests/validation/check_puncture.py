#!/usr/bin/python3
"""Independent cross-check of `hapsim-validate puncture` output.

Rebuilds each layer's force net from its specification only (Table 2's
rings w, spacing L and K; surface springs k_s = K of rest length L / 1.02,
zero-length virtual springs K, a rim traction holding the rest lattice) with
its own hexagonal lattice and its own energy minimisation (scipy), and
compares, at every depth the scene tabulated, the force on the tip and the
mean deflection Z_j of every ring (net_tables.csv). Then checks that each
layer was pierced where its own solve reaches the layer's puncture force
(punctures.csv, skin: along z), the Table 1 withdrawal law, and springback.
Usage: check_puncture.py OUT_DIR  (exit 0 = all checks pass)
"""
import csv
import sys

import numpy as np
import scipy.optimize

SURFACE_RATIO, PRESTRETCH = 1.0, 0.02             # scene defaults
LAYERS = [  # name, thickness mm, K N/m, w, L m, puncture force N (0.3 mm needle)
    ("skin", 0.8, 160.0, 8, 2.0e-3, 1.0),
    ("fat", 8.4, 80.0, 4, 1.0e-3, 0.2),
    ("muscle", 39.0, 230.0, 10, 2.5e-3, 1.5),
]
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


def hex_net(w, L):
    nodes = [(q, r) for q in range(-w + 1, w) for r in range(-w + 1, w) if max(abs(q), abs(r), abs(q + r)) <= w - 1]
    index = {n: i for i, n in enumerate(nodes)}
    X = np.array([[L * (q + r / 2), L * r * np.sqrt(3) / 2, 0.0] for q, r in nodes])
    springs = [(i, index[(q + dq, r + dr)]) for (q, r), i in index.items()
               for dq, dr in ((1, 0), (0, 1), (-1, 1)) if (q + dq, r + dr) in index]
    ring = np.array([max(abs(q), abs(r), abs(q + r)) + 1 for q, r in nodes])
    return X, np.array(springs), ring, index[(0, 0)]


def solve_net(w, L, K, depths):
    """Force on the tip and ring deflections Z_j (m) at each depth."""
    X, S, ring, centre = hex_net(w, L)
    ks, L0 = SURFACE_RATIO * K, L / (1 + PRESTRETCH)

    def internal(x):
        d = x[S[:, 1]] - x[S[:, 0]]
        length = np.linalg.norm(d, axis=1)
        f = (ks * (length - L0) / length)[:, None] * d
        F = np.zeros_like(x)
        np.add.at(F, S[:, 0], f)
        np.add.at(F, S[:, 1], -f)
        return F

    traction = -internal(X)  # holds the rest lattice
    free = np.array([i for i in range(len(X)) if i != centre])
    x = X.copy()
    out = []
    for depth in depths:
        x[centre] = X[centre] + [0.0, 0.0, -depth]

        def energy(y):
            xx = x.copy()
            xx[free] = y.reshape(-1, 3)
            d = xx[S[:, 1]] - xx[S[:, 0]]
            length = np.linalg.norm(d, axis=1)
            e = 0.5 * ks * np.sum((length - L0) ** 2) + 0.5 * K * np.sum((xx - X) ** 2) - np.sum(traction * xx)
            grad = -internal(xx) + K * (xx - X) - traction
            return e, grad[free].ravel()

        r = scipy.optimize.minimize(energy, x[free].ravel(), jac=True, method="L-BFGS-B",
                                    options={"maxiter": 20000, "gtol": 1e-13, "ftol": 1e-20, "maxcor": 30})
        x[free] = r.x.reshape(-1, 3)
        force = -K * np.sum(x[:, 2] - X[:, 2])
        z = [-(x[ring == j, 2] - X[ring == j, 2]).mean() for j in range(1, w + 1)]
        out.append((force, z))
    return out


def main(out):
    tables = {}
    for r in csv.DictReader(open(f"{out}/net_tables.csv")):
        t = tables.setdefault(int(r["layer"]), {})
        t.setdefault(float(r["depth_mm"]), {})[int(r["ring"])] = (float(r["force_N"]), float(r["Z_mm"]))
    puncture_depth_mm = []
    for i, (name, _, K, w, L, fp) in enumerate(LAYERS):
        depths_mm = sorted(tables[i])
        ours = solve_net(w, L, K, [1e-3 * d for d in depths_mm])
        worst_f = worst_z = 0.0
        forces = []
        for d, (force, z) in zip(depths_mm, ours):
            row = tables[i][d]
            worst_f = max(worst_f, abs(row[1][0] - force))
            worst_z = max(worst_z, max(abs(row[j][1] - 1e3 * z[j - 1]) for j in range(1, w + 1)))
            forces.append(force)
        check(worst_f < 1e-6 and worst_z < 1e-6,
              f"{name}: the scene's net table matches an independent solve at {len(depths_mm)} depths "
              f"(force within {worst_f:.1e} N, every ring's Z within {worst_z:.1e} mm)")
        # Where this solve reaches the puncture force (linear between the solves).
        k = next(k for k, f in enumerate(forces) if f >= fp)
        dp = depths_mm[k - 1] + (fp - forces[k - 1]) / (forces[k] - forces[k - 1]) * (depths_mm[k] - depths_mm[k - 1])
        puncture_depth_mm.append(dp)
        print(f"     {name}: puncture force {fp} N reached at {dp:.6f} mm of indentation")
    check(2.0 <= puncture_depth_mm[0] <= 6.0, f"skin indents {puncture_depth_mm[0]:.3f} mm before it gives way (2-6 mm)")

    rows = list(csv.DictReader(open(f"{out}/punctures.csv")))
    skin = next(r for r in rows if r["name"] == "skin")
    # The skin's normal at the site is +z: pierced at the first 5 µm tick at
    # or past the indentation this solve gives.
    depth = float(skin["depth_mm"])
    check(puncture_depth_mm[0] - 1e-6 <= depth <= puncture_depth_mm[0] + 5e-3 + 1e-6,
          f"skin pierced at {depth:.4f} mm, the first tick past {puncture_depth_mm[0]:.4f} mm")

    # Withdrawal (the validation runs Table 1's law): F = -(sum d_i h_i) v.
    fd = list(csv.DictReader(open(f"{out}/force_depth.csv")))
    depth_mm = np.array([float(r["depth_mm"]) for r in fd])
    force = np.array([float(r["force_N"]) for r in fd])
    t = np.array([float(r["t_s"]) for r in fd])
    turn = int(np.argmax(depth_mm))
    v = (depth_mm[turn] - depth_mm[turn - 200]) / (t[turn] - t[turn - 200]) * 1e-3
    d_per_mm = [3.0, 1.0, 3.0]
    worst = 0.0
    for dmm, f in zip(depth_mm[turn + 1:], force[turn + 1:]):
        if dmm <= 0.0:
            continue
        b, top = 0.0, 0.0
        for (_, h, *_), d in zip(LAYERS, d_per_mm):
            b += d * min(max(dmm - top, 0.0), h)
            top += h
        worst = max(worst, abs(f + b * v))
    check(worst < 1e-5, f"withdrawal force = -(sum d_i h_i) v at every tick (worst {worst:.1e} N)")

    # The scene's default shaft law, simulated here from the poses alone with
    # the documented defaults (docs/validation.md#shaft-friction): Coulomb
    # skin 10, fat 5, muscle 15 N per m inserted; a tenth of Table 1's
    # damping; stick spring 300 N/m. The shaft sticks where the skin gave way;
    # the friction is that spring clamped to the Coulomb level, and the
    # stick point slides by the excess. Compared where no surface is being
    # pressed (there the net's reaction adds).
    coulomb_per_m, d_per_m2, visc_scale, k_stick = [10.0, 5.0, 15.0], [3000.0, 1000.0, 3000.0], 0.1, 300.0
    thickness_m = [1e-3 * h for (_, h, *_) in LAYERS]
    stick = None
    worst, compared, at30 = 0.0, 0, None
    for r in csv.DictReader(open(f"{out}/shaft_friction_default.csv")):
        z, v, punctured = float(r["tip_z_m"]), float(r["v_z_m_per_s"]), int(r["punctured"])
        if punctured == 0:
            stick = None
            continue
        if stick is None:
            stick = z  # the tick the skin gave way
        coulomb = damping = 0.0
        top = 0.0
        for i in range(punctured):
            inside = min(max(-z - top, 0.0), thickness_m[i])
            coulomb += coulomb_per_m[i] * inside
            damping += visc_scale * d_per_m2[i] * inside
            top += thickness_m[i]
        e = -(z - stick)  # along the axis, which points down
        held = min(max(e, -coulomb / k_stick), coulomb / k_stick)
        stick -= e - held
        expected = k_stick * held - damping * v
        if r["pressing"] == "0":
            worst = max(worst, abs(float(r["force_z_N"]) - expected))
            compared += 1
        if at30 is None and abs(z + 30e-3) < 1e-12:
            at30 = float(r["force_z_N"])
    check(compared > 1000 and worst < 1e-9,
          f"default stick-slip shaft law matches an independent simulation at {compared} ticks (worst {worst:.1e} N)")
    check(at30 is not None and 0.005 <= at30 / 30.0 <= 0.05,
          f"default shaft friction at 30 mm, 10 mm/s: {at30:.3f} N = {at30 / 30.0:.4f} N/mm (order 1e-2 N/mm)")

    sb = list(csv.DictReader(open(f"{out}/springback.csv")))
    offsets = [float(r["offset_mm"]) for r in sb]
    check(len(offsets) > 10 and offsets[-1] > 0.0, f"skin springs back above the tip reference line ({offsets[-1]:.4f} mm)")
    sys.exit(1 if failures else 0)


main(sys.argv[1])
