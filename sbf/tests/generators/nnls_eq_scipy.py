"""Pinned oracle values for sbf/tests/nnls_eq.rs `matches_scipy` (NNLS under equality
constraints, min ½bᵀGb − mᵀb subject to b ≥ 0, C b = d).

Independent of sbf: scipy solves each problem two ways and the script checks that they
agree before printing the Rust literals pasted into the test.
  1. Lawson & Hanson's weighting method (Solving Least Squares Problems, 1974, ch. 22):
     scipy.optimize.nnls on [Lᵀ; w C] b ≈ [L⁻¹m; w d] with G = L Lᵀ, for w = 1e3…1e6, then
     Richardson extrapolation in 1/w² (the method's error is a power series in 1/w²).
  2. scipy.optimize.minimize(method="SLSQP") with the equality and bound constraints.
Run: python3 -m venv /tmp/v && /tmp/v/bin/pip install scipy numpy &&
     /tmp/v/bin/python sbf/tests/generators/nnls_eq_scipy.py
Generated with scipy 1.17.1, numpy (see --version output below), 2026-12-06.
"""
import numpy as np
import scipy
from scipy.optimize import nnls, minimize

# Each problem: A (G = AᵀA + ridge·I, ridge 0 unless given), m, C, d — small decimals, written out identically in the test.
PROBLEMS = [
    # n 4, one row: plain NNLS keeps too much of the first lobe; the row pins the sum.
    dict(A=[[1.0, 0.6, 0.2, 0.0], [0.0, 1.0, 0.5, 0.1], [0.0, 0.0, 1.0, 0.4], [0.0, 0.0, 0.0, 1.0], [0.3, 0.3, 0.3, 0.3]],
         m=[2.0, 0.5, -0.3, 1.4], C=[[1.0, 1.0, 1.0, 1.0]], d=[1.5]),
    # n 5, two rows with mixed signs; the solution has two zeros.
    dict(A=[[2.0, 0.1, 0.0, 0.3, 0.0], [0.0, 1.5, 0.2, 0.0, 0.1], [0.1, 0.0, 1.0, 0.2, 0.0], [0.0, 0.3, 0.0, 0.8, 0.2], [0.0, 0.0, 0.4, 0.0, 1.2], [0.5, 0.5, 0.5, 0.5, 0.5]],
         m=[1.0, -0.5, 0.8, 0.2, -0.1], C=[[0.2, 0.4, 0.6, 0.8, 1.0], [1.0, -1.0, 0.5, 0.0, 0.3]], d=[0.9, 0.1]),
    # n 6, one row, nearly collinear columns (cond(G) ≈ 1e4): SG-like overlapping lobes.
    dict(A=[[1.0, 0.98, 0.9, 0.7, 0.45, 0.2], [0.2, 0.45, 0.7, 0.9, 0.98, 1.0], [0.5, 0.6, 0.7, 0.7, 0.6, 0.5], [0.0, 0.1, 0.0, 0.1, 0.0, 0.1], [0.1, 0.0, 0.1, 0.0, 0.1, 0.0], [0.3, 0.2, 0.1, 0.1, 0.2, 0.3], [0.05, 0.0, 0.0, 0.0, 0.0, 0.05]],
         m=[1.2, 0.3, 1.3, 0.4, -0.2, 1.1], C=[[0.9, 0.7, 0.4, 0.4, 0.7, 0.9]], d=[1.8], ridge=1e-4),
    # n 3, one row that binds a coefficient plain NNLS would leave at 0.
    dict(A=[[1.0, 0.5, 0.0], [0.0, 1.0, 0.5], [0.2, 0.0, 1.0]],
         m=[1.0, 1.0, -1.0], C=[[0.0, 0.0, 1.0]], d=[0.25]),
]


def weighted(G, m, C, d, w):
    L = np.linalg.cholesky(G)
    A = np.vstack([L.T, w * C])
    y = np.concatenate([np.linalg.solve(L, m), w * d])
    return nnls(A, y, maxiter=10000)[0]


def solve(p):
    A = np.array(p["A"]); G = A.T @ A + p.get("ridge", 0.0) * np.eye(A.shape[1])
    m = np.array(p["m"]); C = np.array(p["C"]); d = np.array(p["d"])
    # Richardson in h = 1/w²: b(h) = b0 + c1 h + c2 h² …, three weights a factor 10 apart.
    ws = [1e3, 1e4, 1e5]
    bs = [weighted(G, m, C, d, w) for w in ws]
    h = [1.0 / w**2 for w in ws]
    # Fit b(h) quadratic through the three points, evaluate at h = 0.
    V = np.vander(h, 3, increasing=True)
    b_rich = np.linalg.solve(V, np.array(bs))[0]
    b_rich[np.abs(b_rich) < 1e-14] = 0.0
    cons = [dict(type="eq", fun=lambda b: C @ b - d, jac=lambda b: C)]
    r = minimize(lambda b: 0.5 * b @ G @ b - m @ b, np.full(len(m), 0.1), jac=lambda b: G @ b - m,
                 bounds=[(0, None)] * len(m), constraints=cons, method="SLSQP",
                 options=dict(ftol=1e-16, maxiter=1000))
    gap = np.max(np.abs(r.x - b_rich)) / max(1.0, np.max(np.abs(b_rich)))
    plain = nnls(np.linalg.cholesky(G).T, np.linalg.solve(np.linalg.cholesky(G), m))[0]
    return G, b_rich, r.x, gap, np.linalg.cond(G), plain


print(f"// scipy {scipy.__version__}, numpy {np.__version__}")
for i, p in enumerate(PROBLEMS):
    G, b, s, gap, cond, plain = solve(p)
    print(f"// problem {i}: cond(G) {cond:.2e}; weighting+Richardson vs SLSQP max gap {gap:.1e}; "
          f"plain NNLS {np.array2string(plain, precision=6)}; C·plain {np.array(p['C']) @ plain}")
    assert gap < 1e-7, gap
    print("    &[" + ", ".join(f"{v:.15e}" for v in b) + "],")
