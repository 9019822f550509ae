"""Variable projection of FRFs that share one design (the same lines): the tail columns projected out, each
FRF's massline, the curvature of its RSS and its tail coefficients (the reduction of :mod:`.tails`).

Over [Re; Im] of the design's 2n values, with tail columns X (2n, k) and the massline's column u (1 on the real
parts), the projector P = I − QQᵀ (Q spanning X) leaves RSS(A) = ‖PY − A Pu‖², a parabola of curvature κ = ‖Pu‖²
about â = (Pu)ᵀPY/κ (Golub & Pereyra 1973's separable least squares).
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import solve_triangular


def spanning(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Q (2n, k) with orthonormal columns spanning X's and R (k, k) with X = QR (the reduced QR)."""
    return np.linalg.qr(X)


def project_out(X: np.ndarray, Y: np.ndarray, u: np.ndarray, Q: np.ndarray | None = None):
    """(I − QQᵀ) of the kept columns u (the massline's, (2n,) or (2n, m)) and of the data Y (…, 2n), Q spanning
    X's columns (given, or from X)."""
    if X.shape[1] == 0:
        return u, Y
    Q = spanning(X)[0] if Q is None else Q
    return u - Q @ (Q.T @ u), Y - (Y @ Q) @ Q.T


def coefficients(X: np.ndarray, Q: np.ndarray, R: np.ndarray, rest: np.ndarray) -> np.ndarray:
    """The least-squares coefficients c (…, k) of ``rest`` (…, 2n) ≈ X c: R⁻¹ Qᵀ rest from X's QR, or the
    minimum-norm solution where R is singular to working precision (|R_kk| ≤ 2n·ε·max |R_kk|, as lstsq's cutoff)."""
    diagonal = np.abs(np.diag(R))
    flat = rest.reshape(-1, X.shape[0]).T
    if diagonal.min() <= X.shape[0] * np.finfo(float).eps * diagonal.max():
        solved = np.linalg.lstsq(X, flat, rcond=None)[0]
    else:
        solved = solve_triangular(R, Q.T @ flat)
    return solved.T.reshape(*rest.shape[:-1], -1)


def reduce_design(X: np.ndarray, unit: np.ndarray, values: np.ndarray) -> tuple:
    """One design's reduction: the masslines, κ, the RSS and the tail coefficients of the FRFs ``values`` (…, 2n)
    on the tail columns X (2n, k) and the massline's column ``unit`` (2n,) of their lines."""
    Q, R = spanning(X) if X.shape[1] else (None, None)
    u, PY = project_out(X, values, unit, Q)
    kappa = float(u @ u)
    massline = PY @ u / kappa
    rss = np.sum((PY - massline[..., None] * u) ** 2, axis=-1)  # not ‖PY‖² − κâ²: that cancels
    if X.shape[1]:
        tails = coefficients(X, Q, R, values - massline[..., None] * unit)
    else:
        tails = np.zeros((*massline.shape, 0))
    return massline, kappa, rss, tails


def support_design(X: np.ndarray, unit: np.ndarray, values: np.ndarray) -> tuple:
    """One design's reduction keeping the support column X[:, 0]: (â, b̂) (…, 2), the RSS and K₂ (2, 2)."""
    D, PY = project_out(X[:, 1:], values, np.column_stack([unit, X[:, 0]]))
    K2 = D.T @ D
    ab = np.linalg.solve(K2, (PY @ D)[..., None])[..., 0]
    rss = np.sum((PY - ab @ D.T) ** 2, axis=-1)
    return ab, rss, K2
