#!/usr/bin/python3
"""Independent cross-check of `hapsim-validate shf` output with scipy.

1. Real SH values (sh_values.csv) against scipy.special.sph_harm: for m > 0
   Y_lm = sqrt(2) Re Y_l^m, m < 0: sqrt(2) Im Y_l^|m|, m = 0: Y_l^0 (scipy's
   complex Y_l^m includes the Condon-Shortley phase, as ours does).
2. An independent least-squares fit of star.obj at Lmax 9 (numpy lstsq on a
   scipy-built basis, radial parametrisation) must reproduce the C++ RMS
   residual in fit_error.csv.
3. fit_error.csv claims: ellipsoid natural fit exact; RMS error falls with Lmax.
Usage: check_shf.py OUT_DIR   (exit 0 = all checks pass)
"""
import csv
import sys

import numpy as np
from scipy.special import sph_harm


def real_sh(l, m, theta, phi):
    if m == 0:
        return sph_harm(0, l, phi, theta).real
    y = sph_harm(abs(m), l, phi, theta)
    return np.sqrt(2.0) * (y.real if m > 0 else y.imag)


def main(out):
    ok = True
    rows = list(csv.DictReader(open(f"{out}/sh_values.csv")))
    worst = 0.0
    for r in rows:
        l, m = int(r["l"]), int(r["m"])
        ref = real_sh(l, m, float(r["theta_rad"]), float(r["phi_rad"]))
        worst = max(worst, abs(float(r["value"]) - ref))
    good = worst < 1e-10
    ok &= good
    print(f"SH values vs scipy.special.sph_harm ({len(rows)} values, l<=30): max |diff| = {worst:.2e}  {'ok' if good else 'FAIL'}")

    # Independent fit of the OBJ mesh.
    verts = np.array([[float(x) for x in line.split()[1:4]] for line in open(f"{out}/star.obj") if line.startswith("v ")])
    theta = np.arctan2(np.hypot(verts[:, 0], verts[:, 1]), verts[:, 2])
    phi = np.arctan2(verts[:, 1], verts[:, 0])
    lmax = 9
    Y = np.column_stack([real_sh(l, m, theta, phi) for l in range(lmax + 1) for m in range(-l, l + 1)])
    coef, *_ = np.linalg.lstsq(Y, verts, rcond=None)
    rms_mm = 1e3 * np.sqrt(np.mean(np.sum((Y @ coef - verts) ** 2, axis=1)))
    fit_rows = list(csv.DictReader(open(f"{out}/fit_error.csv")))
    cpp = [float(r["rms_residual_mm"]) for r in fit_rows if r["body"] == "obj_star" and int(r["lmax"]) == lmax][0]
    good = abs(rms_mm - cpp) <= 1e-6 * cpp
    ok &= good
    print(f"star.obj Lmax {lmax} RMS residual: numpy {rms_mm:.9e} mm, C++ {cpp:.9e} mm  {'ok' if good else 'FAIL'}")

    nat = max(float(r["holdout_max_error_mm"]) for r in fit_rows if r["body"] == "ellipsoid_natural")
    good = nat < 1e-11
    ok &= good
    print(f"ellipsoid natural parametrisation: max held-out error {nat:.2e} mm  {'ok' if good else 'FAIL'}")
    for body in ("limb_segment", "ellipsoid_radial", "obj_star"):
        e = [float(r["holdout_rms_error_mm"]) for r in fit_rows if r["body"] == body]
        good = all(b <= a * (1 + 1e-9) or b < 1e-6 for a, b in zip(e, e[1:])) and e[-1] < 0.01 * e[0]
        ok &= good
        print(f"{body}: held-out RMS error {e[0]:.3g} -> {e[-1]:.3g} mm, falling  {'ok' if good else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: check_shf.py OUT_DIR")
    sys.exit(main(sys.argv[1]))
