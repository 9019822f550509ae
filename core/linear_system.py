"""Solving the paper's linear systems, with their condition numbers.

Square systems are solved exactly, overdetermined ones by least squares; a
system that is rank deficient is never solved but reported with the reason
(the caller knows the physics and passes it in).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from massline.core.errors import SingularLayoutError

RANK_TOLERANCE = 1e-10  # smallest singular value relative to the largest


def solve(A: np.ndarray, b: np.ndarray, system: str, why: str | Callable[[], str]) -> tuple[np.ndarray, float]:
    """Solve A x = b (least squares when overdetermined); return x and κ(A).

    Parameters
    ----------
    A : (n_equations, n_unknowns) coefficient matrix.
    b : (n_equations,) or (n_equations, k) known terms.
    system : name of the system for messages, e.g. "kinematics, eq. (6)".
    why : the physical reason a rank deficiency would have (or a function
        returning it, evaluated only when needed).
    """
    n_eq, n_unknown = A.shape
    reason = why if isinstance(why, str) else None
    if n_eq < n_unknown:
        reason = reason or why()
        raise SingularLayoutError(f"{system}: {n_eq} equations for {n_unknown} unknowns; add measurements ({reason})")
    s = np.linalg.svd(A, compute_uv=False)
    if s[0] == 0 or s[-1] < RANK_TOLERANCE * s[0]:
        deficiency = int(np.sum(s < RANK_TOLERANCE * max(s[0], 1e-300)))
        reason = reason or why()
        raise SingularLayoutError(f"{system} is singular (rank {n_unknown - deficiency} of {n_unknown}): {reason}")
    if n_eq == n_unknown:
        x = np.linalg.solve(A, b)
    else:
        x = np.linalg.lstsq(A, b, rcond=None)[0]
    return x, float(s[0] / s[-1])
