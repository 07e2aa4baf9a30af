#!/usr/bin/python3
"""Independent cross-check of `hapsim-validate vessel` output.

The flat punch: the validation presses a rigid, frictionless flat punch
into a meshless block bonded to a rigid base (flat_punch.csv: its nodes,
modulus, the punch's effective radius and depth, the force it took). This
solves the same problem for a continuum with its own finite elements
(axisymmetric bilinear quads, 2x2 Gauss, scipy's sparse solver; a cylinder of
the block's footprint area), converged by halving the element size twice and
extrapolating, for the two ways to read a block of nodes as a body — the
nodes' extent and the nodes' volumes (half a spacing more on every free
side) — and checks the meshless force against that range within 10 % (the
punch's edge falls between nodes 1 mm apart). The finite-element code is
first checked on a slender cylinder pressed end on (force E A d / H).
Usage: check_vessel.py OUT_DIR  (exit 0 = all checks pass)
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


def punch_force(E, nu, a, R, H, h, depth=1e-5):
    """Force [N] of a rigid frictionless flat punch (radius a, pressed depth) on an elastic cylinder (radius R,
    height H) bonded to a rigid base; axisymmetric bilinear quads of size ~h with a node at r = a."""
    nr, nz = int(round(R / h)), int(round(H / h))
    r_nodes = np.linspace(0.0, R, nr + 1)
    r_nodes[int(np.argmin(abs(r_nodes - a)))] = a
    z_nodes = np.linspace(0.0, H, nz + 1)
    NR, NZ = nr + 1, nz + 1
    lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    # Strains (e_rr, e_zz, e_tt, g_rz).
    D = np.array([[lam + 2 * mu, lam, lam, 0], [lam, lam + 2 * mu, lam, 0], [lam, lam, lam + 2 * mu, 0], [0, 0, 0, mu]])
    I, J = (g.ravel() for g in np.meshgrid(np.arange(nr), np.arange(nz), indexing="ij"))

    def nid(i, j):
        return j * NR + i

    conn = np.stack([nid(I, J), nid(I + 1, J), nid(I + 1, J + 1), nid(I, J + 1)], axis=1)
    r0, hr, hz = r_nodes[I], r_nodes[I + 1] - r_nodes[I], z_nodes[J + 1] - z_nodes[J]
    sr, sz = np.array([-1, 1, 1, -1]), np.array([-1, -1, 1, 1])
    Ke = np.zeros((len(conn), 8, 8))
    for xi in (-1 / math.sqrt(3), 1 / math.sqrt(3)):
        for eta in (-1 / math.sqrt(3), 1 / math.sqrt(3)):
            N = (1 + sr * xi) * (1 + sz * eta) / 4
            dNr = (sr * (1 + sz * eta) / 4)[None, :] / (hr[:, None] / 2)
            dNz = (sz * (1 + sr * xi) / 4)[None, :] / (hz[:, None] / 2)
            r = r0 + (xi + 1) / 2 * hr
            B = np.zeros((len(conn), 4, 8))
            B[:, 0, 0::2] = dNr
            B[:, 1, 1::2] = dNz
            B[:, 2, 0::2] = N[None, :] / r[:, None]
            B[:, 3, 0::2] = dNz
            B[:, 3, 1::2] = dNr
            Ke += np.einsum("eki,kl,elj,e->eij", B, D, B, 2 * math.pi * r * hr * hz / 4)
    dofs = (2 * conn[:, :, None] + np.arange(2)).reshape(len(conn), 8)
    n = 2 * NR * NZ
    K = scipy.sparse.csr_matrix(
        (Ke.reshape(-1), (np.repeat(dofs, 8, axis=1).ravel(), np.tile(dofs, (1, 8)).ravel())), shape=(n, n))
    ii, jj = (g.ravel() for g in np.meshgrid(np.arange(NR), np.arange(NZ), indexing="ij"))
    ids = nid(ii, jj)
    u, fixed = np.zeros(n), np.zeros(n, bool)
    base = ids[jj == 0]
    fixed[2 * base] = fixed[2 * base + 1] = True  # bonded to the rigid base
    fixed[2 * ids[ii == 0]] = True                # u_r = 0 on the axis
    pressed = 2 * ids[(jj == nz) & (r_nodes[ii] <= a + 1e-15)] + 1
    fixed[pressed] = True                         # u_z = -depth under the punch, u_r free (frictionless)
    u[pressed] = -depth
    free = ~fixed
    u[free] = scipy.sparse.linalg.spsolve(K[free][:, free].tocsc(), -K[free][:, fixed] @ u[fixed])
    return -(K @ u)[pressed].sum()


def converged(E, nu, a, R, H, h):
    """Richardson extrapolation over h, h/2 (first order in the element size: the punch's edge)."""
    coarse, fine = punch_force(E, nu, a, R, H, h), punch_force(E, nu, a, R, H, h / 2)
    return 2 * fine - coarse, abs(fine - coarse)


# The finite elements on a problem with a known answer: a slender cylinder
# (R = 1 mm, H = 20 mm) pressed over its whole top: E pi R^2 d / H, up to
# the bonded ends (~0.3 % at this slenderness).
slender = punch_force(1e5, 0.3, 1e-3, 1e-3, 20e-3, 1e-4)
check(abs(slender / (1e5 * math.pi * 1e-6 * 1e-5 / 20e-3) - 1) < 0.005,
      f"finite elements: slender cylinder pressed end on, force / (E A d / H) = "
      f"{slender / (1e5 * math.pi * 1e-6 * 1e-5 / 20e-3):.4f}")

p = {k: float(v) for k, v in next(csv.DictReader(open(f"{out}/flat_punch.csv"))).items()}
E, nu, a, s = p["youngs_modulus_Pa"], p["poisson_ratio"], p["punch_radius_m"], p["spacing_m"]
half_space = 2 * a * E * p["depth_m"] / (1 - nu * nu)
readings = {
    "the nodes' extent": ((p["nodes_x"] - 1) * s, (p["nodes_z"] - 1) * s),
    "the nodes' volumes": (p["nodes_x"] * s, (p["nodes_z"] - 0.5) * s),
}
ratios = []
for name, (side, height) in readings.items():
    force, change = converged(E, nu, a, side / math.sqrt(math.pi), height, 1e-4)
    force *= p["depth_m"] / 1e-5
    ratios.append(force / half_space)
    print(f"     {name}: {side * 1e3:.1f} mm square footprint, {height * 1e3:.1f} mm thick: force / half-space "
          f"{ratios[-1]:.4f} (halving the elements changed it {100 * change * p['depth_m'] / 1e-5 / force:.2f} %)")
meshless = p["force_N"] / half_space
lo, hi = min(ratios), max(ratios)
check(0.9 * lo <= meshless <= 1.1 * hi,
      f"flat punch on the meshless block: force / half-space {meshless:.4f}, the same block as a continuum "
      f"{lo:.4f}-{hi:.4f} (within 10 %: {100 * (meshless / lo - 1):+.1f} % of the lower reading)")
sys.exit(1 if failures else 0)
