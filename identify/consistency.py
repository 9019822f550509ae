"""Physical consistency: the bodies a parameter vector θ can be.

θ = (m, m c, J_O six, tensor sign) is a body's when its pseudo-inertia matrix (Wensing, Kim & Slotine 2017)

    P(θ) = [[½ tr(J_O) I − J_O, m c], [m cᵀ, m]]

is positive definite: its upper block is the body's second moments ∫ r rᵀ dm about O. P is linear in θ, so the
bodies form a convex cone, and the estimator's step that leaves it is taken again as the least-squares step
inside it.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np

from massline.core.band import GIVE_BAND
from massline.core.errors import MasslineError
from massline.core.model import RigidModel
from massline.core.rigid_body import tensor_from_six

CONSISTENCY_MARGIN = 1e-9  # smallest eigenvalue of P kept, relative to m L²


def pseudo_inertia(theta: np.ndarray) -> np.ndarray:
    """P(θ) (4×4, kg·m², kg·m, kg) from θ = (m, m c, J_O six, tensor sign)."""
    J = tensor_from_six(theta[4:])
    P = np.zeros((4, 4))
    P[:3, :3] = 0.5 * np.trace(J) * np.eye(3) - J
    P[:3, 3] = P[3, :3] = theta[1:4]
    P[3, 3] = theta[0]
    return P


def is_consistent(theta: np.ndarray, scale: float) -> bool:
    return bool(np.linalg.eigvalsh(pseudo_inertia(theta)).min() > CONSISTENCY_MARGIN * scale)


def constrained_step(J: np.ndarray, r: np.ndarray, theta: np.ndarray, model: RigidModel) -> np.ndarray:
    """argmin ‖J δ − r‖² subject to P(θ + scale·δ[:p]) ⪰ ε I (δ in scaled parameters, then any others).

    P is linear in δ: P(θ) + Σ_k δ_k P(scale_k e_k). The constraint is posed as S P S ⪰ ε S², S = diag(P(θ))^-½
    (the same cone, its numbers near 1 for the solver), and J, r as J/u, r/u with u = max |J|."""
    import cvxpy as cp

    problem, delta, (A, b, basis, offset) = _step_problem(*J.shape, model.p)
    unit = max(float(np.abs(J).max()), 1e-300)
    S = np.diag(1 / np.sqrt(np.maximum(np.abs(np.diag(pseudo_inertia(theta))), 1e-300)))
    A.value, b.value = J / unit, r / unit
    for k, C in enumerate(basis):
        C.value = _symmetric(S @ pseudo_inertia(np.eye(10)[k] * model.scale[k]) @ S)
    offset.value = _symmetric(S @ pseudo_inertia(theta) @ S - CONSISTENCY_MARGIN * model.scale[-1] * S @ S)
    with warnings.catch_warnings():  # an inaccurate solution is judged below, by its status, not printed
        warnings.simplefilter("ignore", UserWarning)
        try:
            problem.solve(solver=cp.CLARABEL)
        except cp.error.SolverError:  # the solver gave up: no step, as an infeasible status
            delta.value = None
    if problem.status not in (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) or delta.value is None:
        raise MasslineError(
            "the estimate leaves the physical bodies and no physical step fits the masslines (a flipped or "
            f"swapped channel, or a band across a resonance?); run massline diagnose, or give {GIVE_BAND}"
        )
    return np.asarray(delta.value)


def _symmetric(M: np.ndarray) -> np.ndarray:
    return (M + M.T) / 2


@functools.lru_cache(maxsize=16)
def _step_problem(rows: int, columns: int, p: int):
    """The constrained step's problem for J of shape (``rows``, ``columns``) and ``p`` body parameters, with its
    data as parameters (J/u, r/u, the p scaled basis matrices of P, its offset): compiled once per shape, each
    solve then fills the values in (cvxpy's DPP; building it anew took 18 of the 20 ms a step took)."""
    import cvxpy as cp

    delta = cp.Variable(columns)
    A, b = cp.Parameter((rows, columns)), cp.Parameter(rows)
    basis = [cp.Parameter((4, 4), symmetric=True) for _ in range(p)]
    offset = cp.Parameter((4, 4), symmetric=True)
    P = offset + sum(C * delta[k] for k, C in enumerate(basis))
    problem = cp.Problem(cp.Minimize(cp.sum_squares(A @ delta - b)), [P >> 0])
    return problem, delta, (A, b, basis, offset)
