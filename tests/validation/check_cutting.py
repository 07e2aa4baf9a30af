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
   wound nodes with the simulated ones after 2 s of settling (within 2 %).
3. The same skin as a continuum: a plane-stress finite-element solve (own
   assembly) of the membrane with the lattice's own modulus (E t = 8 K / 3,
   nu = 1/3) on its anchors as an elastic foundation, slit along the
   incision, against the simulated gape (within 10 %); and the gape the
   paper's E would give, printed.
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

# 3. The same skin as a continuum: a plane-stress membrane (linear
# triangles on a 0.4 mm grid, our own assembly) with the anchors as an
# in-plane elastic foundation (anchor k / spacing^2 per area), the slit where
# the incision runs, and the released traction sigma_r t on its faces.
cont = next(csv.DictReader(open(f"{out}/static_continuum.csv")))
P = {k: float(v) for k, v in cont.items()}


def continuum_gapes(E, nu, h=4e-4):
    """Opening u_y(upper) - u_y(lower) [mm] at x = 0, -5, +5 mm."""
    L, W, t, a, y0 = P["length_m"], P["width_m"], P["thickness_m"], P["spacing_m"], P["incision_y_m"]
    x0, x1 = P["incision_x0_m"], P["incision_x1_m"]

    def axis(lo, hi, cuts):
        pts = sorted(set([lo, hi] + cuts))
        line = [pts[0]]
        for p, q in zip(pts[:-1], pts[1:]):
            line += list(np.linspace(p, q, max(1, int(round((q - p) / h))) + 1)[1:])
        return np.array(line)

    xs, ys = axis(-L / 2, L / 2, [x0, x1]), axis(-W / 2, W / 2, [y0])
    nx, ny = len(xs), len(ys)
    jy, ix0, ix1 = int(np.argmin(abs(ys - y0))), int(np.argmin(abs(xs - x0))), int(np.argmin(abs(xs - x1)))
    n = nx * ny
    upper = {}  # the slit's nodes (tips excluded) get a copy for the side above it
    for i in range(ix0 + 1, ix1):
        upper[i] = n
        n += 1

    def node(i, j, above):
        return upper[i] if (j == jy and above and i in upper) else j * nx + i

    X = np.zeros((n, 2))
    for j in range(ny):
        for i in range(nx):
            X[j * nx + i] = (xs[i], ys[j])
    for i, u in upper.items():
        X[u] = X[jy * nx + i]
    D = E * t / (1 - nu ** 2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    r_, c_, v_ = [], [], []
    area = np.zeros(n)
    for j in range(ny - 1):
        above = j >= jy
        for i in range(nx - 1):
            q = [node(i, j, above), node(i + 1, j, above), node(i + 1, j + 1, above), node(i, j + 1, above)]
            split = [(0, 1, 2), (0, 2, 3)] if (i + j) % 2 == 0 else [(0, 1, 3), (1, 2, 3)]
            for tri in ([q[k] for k in s3] for s3 in split):
                Pt = X[tri]
                A2 = (Pt[1, 0] - Pt[0, 0]) * (Pt[2, 1] - Pt[0, 1]) - (Pt[2, 0] - Pt[0, 0]) * (Pt[1, 1] - Pt[0, 1])
                b = [Pt[1, 1] - Pt[2, 1], Pt[2, 1] - Pt[0, 1], Pt[0, 1] - Pt[1, 1]]
                c = [Pt[2, 0] - Pt[1, 0], Pt[0, 0] - Pt[2, 0], Pt[1, 0] - Pt[0, 0]]
                B = np.zeros((3, 6))
                for k in range(3):
                    B[0, 2 * k], B[1, 2 * k + 1], B[2, 2 * k], B[2, 2 * k + 1] = b[k], c[k], c[k], b[k]
                B /= A2
                Ke = 0.5 * A2 * B.T @ D @ B
                dofs = [2 * tri[k] + d for k in range(3) for d in range(2)]
                for p_ in range(6):
                    for q_ in range(6):
                        r_.append(dofs[p_])
                        c_.append(dofs[q_])
                        v_.append(Ke[p_, q_])
                for k in tri:
                    area[k] += A2 / 6
    kf = P["anchor_k_N_per_m"] / (a * a)
    for k in range(n):
        for d in range(2):
            r_.append(2 * k + d)
            c_.append(2 * k + d)
            v_.append(kf * area[k])
    K = scipy.sparse.csr_matrix((v_, (r_, c_)), shape=(2 * n, 2 * n))
    f = np.zeros(2 * n)
    for i in range(ix0, ix1):
        F = P["residual_stress_Pa"] * t * (xs[i + 1] - xs[i]) / 2
        for ii in (i, i + 1):
            f[2 * node(ii, jy, True) + 1] += F
            f[2 * node(ii, jy, False) + 1] -= F
    u = scipy.sparse.linalg.spsolve(K.tocsc(), f).reshape(n, 2)
    out_mm = []
    for xq in (0.0, -0.005, 0.005):
        i = int(np.argmin(abs(xs - xq)))
        out_mm.append(1e3 * (u[node(i, jy, True), 1] - u[node(i, jy, False), 1]))
    return out_mm


# The lattice (structural and both diagonals K, two-apart K_b = K / 4) is an
# isotropic membrane with nu = 1/3 and E t = 8 K / 3 (strain energy of a
# uniform strain per cell); its own modulus and the paper's E.
Ks, Kb = P["spring_k_N_per_m"], P["bending_k_N_per_m"]
assert abs(Kb - Ks / 4) < 1e-12, "the lattice is isotropic only with K_b = K / 4"
E_lattice = 8 * Ks / (3 * P["thickness_m"])
sims = [float(p["simulated_width_mm"]) for p in rows("static_pairs.csv")]
for (xmm, sim, cont_mm) in zip((0, -5, 5), sims, continuum_gapes(E_lattice, 1 / 3)):
    # 10 %: the lattice is the continuum only on average (its free edges and
    # the cut's new triangles differ), and the lip moves are small (~0.3 mm).
    check(abs(sim - cont_mm) <= 0.10 * cont_mm,
          f"gape at x = {xmm:+d} mm: continuum of the lattice's modulus (E = {E_lattice / 1e3:.0f} kPa, nu = 1/3) "
          f"{cont_mm:.4f} mm, simulation {sim:.4f} mm ({100 * (sim - cont_mm) / cont_mm:+.1f} %)")
paper = continuum_gapes(P["youngs_modulus_Pa"], 1 / 3)
print(f"     the paper's E = {P['youngs_modulus_Pa'] / 1e3:.0f} kPa as a continuum would gape "
      f"{paper[0]:.3f} / {paper[1]:.3f} / {paper[2]:.3f} mm at x = 0 / -5 / +5 mm: the springs (K = {Ks:.0f} N/m) "
      f"are a {E_lattice / P['youngs_modulus_Pa']:.1f}x stiffer skin than the residual stress's E")
sys.exit(1 if failures else 0)
