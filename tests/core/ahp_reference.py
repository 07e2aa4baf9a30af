#!/usr/bin/python3
"""Independent reference values for tests/core/assessment_schemes_test.cpp:
AHP weights, lambda_max and CR computed with numpy's eigen-solver (not
hapsim's Eigen code) for the matrices the test uses. Run it to regenerate
the constants: /usr/bin/python3 tests/core/ahp_reference.py"""
import numpy as np

RI = [0.0, 0.0, 0.58, 0.90, 1.12, 1.24, 1.32, 1.41, 1.45, 1.49]

def ahp(a):
    a = np.array(a, dtype=float)
    vals, vecs = np.linalg.eig(a)
    k = int(np.argmax(vals.real))
    v = np.abs(vecs[:, k].real)
    n = a.shape[0]
    lam = vals[k].real
    ci = (lam - n) / (n - 1)
    return v / v.sum(), lam, ci / RI[n - 1]

matrices = {
    # Saaty's textbook 3x3 example
    "saaty3": [[1, 3, 5], [1/3, 1, 3], [1/5, 1/3, 1]],
    # 4x4 with mild inconsistency
    "four": [[1, 2, 4, 3], [1/2, 1, 3, 2], [1/4, 1/3, 1, 1/2], [1/3, 1/2, 2, 1]],
    # badly inconsistent: 1 > 2 > 3 > 1
    "cycle": [[1, 5, 1/5], [1/5, 1, 5], [5, 1/5, 1]],
}
for name, a in matrices.items():
    w, lam, cr = ahp(a)
    print(f"{name}: weights {' '.join(f'{x:.12f}' for x in w)} lambda_max {lam:.12f} CR {cr:.12f}")
