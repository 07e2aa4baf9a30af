#!/usr/bin/python3
"""Independent cross-checks of `hapsim-validate cutting` output.

1. Collision time: recomputes, from the node grid and the blade's start and
   motion alone, the exact first time a node passes the cutting paper's test
   (both base angles <= 90 deg and distance to the axis < r) by its own
   closed form, and checks the validation's true time and that the detected
   tick is the first 1 kHz tick at or after it.
2. Settled gape: solves the wounded patch as a linear static problem with
   scipy (springs linearised at rest, in-plane anchors, the residual forces
   on the rest geometry) and compares the predicted widths of the paired
   wound nodes with the simulated ones after 2 s of settling (within 2 %); prints the
   plane-stress slit estimate 4 p a / E' for scale.
Usage: check_cutting.py OUT_DIR  (exit 0 = all checks pass)
"""
import csv
import math
import sys

import numpy as np
import scipy.sparse
import scipy.sparse.linalg

out = sys.argv[1]
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += 0 if ok else 1


def rows(name):
    return list(csv.DictReader(open(f"{out}/{name}")))


# 1. Collision times.
nodes = np.array([[float(r["x_m"]), float(r["y_m"]), float(r["z_m"])] for r in rows("collision_nodes.csv")])
times = {float(r["angle_deg"]): r for r in rows("collision_time.csv")}
for s in rows("collision_setup.csv"):
    angle = float(s["angle_deg"])
    p0 = np.array([float(s["tip_x_m"]), float(s["tip_y_m"]), float(s["tip_z_m"])])
    a = np.array([float(s["axis_x"]), float(s["axis_y"]), float(s["axis_z"])])
    a /= np.linalg.norm(a)
    r, length, v = float(s["radius_m"]), float(s["length_m"]), float(s["speed_m_per_s"])
    rel = nodes - p0
    axial = rel @ a
    lateral = np.linalg.norm(rel - np.outer(axial, a), axis=1)
    # Inside at time t: 0 <= axial + v t <= length and lateral < r.
    near = lateral < r
    t_enter = np.maximum(0.0, -axial[near] / v)
    t_leave = (length - axial[near]) / v
    t_true = float(np.min(t_enter[t_enter <= t_leave]))
    row = times[angle]
    true_ms, detected_ms = float(row["true_ms"]), float(row["detected_ms"])
    check(abs(true_ms - 1e3 * t_true) < 1e-6,
          f"{angle:.0f} deg: exact contact {1e3 * t_true:.6f} ms (validation: {true_ms:.6f} ms)")
    first_tick = math.ceil(1e3 * t_true - 1e-9)
    check(abs(detected_ms - first_tick) < 1e-9,
          f"{angle:.0f} deg: detected at {detected_ms:.0f} ms, the first tick at or after the contact ({first_tick} ms)")

# 2. The settled gape by a static solve.
node_rows = rows("static_nodes.csv")
index = {int(r["node"]): i for i, r in enumerate(node_rows)}
n = len(node_rows)
x0 = np.array([[float(r["x_m"]), float(r["y_m"])] for r in node_rows])
f = np.zeros(2 * n)
rows_i, cols_i, vals = [], [], []


def add(i, j, block):
    for p in range(2):
        for q in range(2):
            rows_i.append(2 * i + p)
            cols_i.append(2 * j + q)
            vals.append(block[p, q])


for i, r in enumerate(node_rows):
    add(i, i, float(r["anchor_k_N_per_m"]) * np.eye(2))
    f[2 * i], f[2 * i + 1] = float(r["fx_N"]), float(r["fy_N"])
for s in rows("static_springs.csv"):
    i, j, k = index[int(s["i"])], index[int(s["j"])], float(s["k_N_per_m"])
    d = x0[j] - x0[i]
    L = np.linalg.norm(d)
    e = d / L
    # Linearised at rest: k e e^T (the springs are at rest length there).
    assert abs(L - float(s["rest_m"])) < 1e-12, "a spring not at rest length at rest"
    B = k * np.outer(e, e)
    add(i, i, B)
    add(j, j, B)
    add(i, j, -B)
    add(j, i, -B)
K = scipy.sparse.csr_matrix((vals, (rows_i, cols_i)), shape=(2 * n, 2 * n))
u = scipy.sparse.linalg.spsolve(K.tocsc(), f).reshape(n, 2)
for p in rows("static_pairs.csv"):
    a, b = index[int(p["node_a"])], index[int(p["node_b"])]
    width = 1e3 * np.linalg.norm((x0[a] + u[a]) - (x0[b] + u[b]))
    sim = float(p["simulated_width_mm"])
    # 2 %: the solve is linearised at rest; the lips' rotation and stretch
    # (widths ~0.3 mm on 0.8 mm springs) stay below that.
    check(abs(width - sim) <= 0.02 * width,
          f"gape at x = {float(p['x_mm']):+.0f} mm: static solve {width:.4f} mm, simulation after 2 s {sim:.4f} mm "
          f"({100 * (sim - width) / width:+.1f} %)")

# For scale: plane-stress slit of length 2a under opening traction p in a
# membrane of in-plane modulus E' (the square lattice with edges and both
# diagonals K and two-apart springs K_b along x: C11 = 2K + 4K_b, C12 = K,
# E' = C11 - C12^2/C11), no substrate: delta_max = 4 p a / E'.
K_s, K_b, p_traction, a_half = 160.0, 40.0, 2000.0 * 0.002, 0.01
c11, c12 = 2 * K_s + 4 * K_b, K_s
e_prime = c11 - c12 ** 2 / c11
print(f"     slit estimate (intact lattice, no substrate): 4 p a / E' = {1e3 * 4 * p_traction * a_half / e_prime:.3f} mm "
      f"(E' = {e_prime:.1f} N/m); the in-plane anchors under every node hold the lips closer than that")
sys.exit(1 if failures else 0)
