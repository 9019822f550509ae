"""Physical consistency: the bodies a parameter vector θ can be.

θ = (m, m c, J_O six, tensor sign) is a body's when its pseudo-inertia matrix (Wensing, Kim & Slotine 2017)

    P(θ) = [[½ tr(J_O) I − J_O, m c], [m cᵀ, m]]

is positive definite: its upper block is the body's second moments ∫ r rᵀ dm about O. P is linear in θ, so the
bodies form a convex cone, and the estimator's step that leaves it is taken again as the least-squares step
inside it.
"""

from __future__ import annotations

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
    """argmin ‖J δ − r‖² subject to P(θ + scale·δ[:p]) ⪰ ε I (δ in scaled parameters, then any others)."""
    import cvxpy as cp

    delta = cp.Variable(J.shape[1])
    P = sum(pseudo_inertia(np.eye(10)[k] * model.scale[k]) * delta[k] for k in range(model.p))
    P = P + pseudo_inertia(theta)
    epsilon = CONSISTENCY_MARGIN * model.scale[-1]
    unit = max(float(np.abs(J).max()), 1e-300)  # the same problem, with its numbers near 1 for the solver
    objective = cp.sum_squares((J / unit) @ delta - r / unit)
    scale = np.diag(1 / np.sqrt(np.maximum(np.abs(np.diag(pseudo_inertia(theta))), 1e-300)))
    psd = scale @ ((P + P.T) / 2) @ scale >> epsilon * scale @ scale
    problem = cp.Problem(cp.Minimize(objective), [psd])
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
