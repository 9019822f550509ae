"""The best estimator: all masslines at once, weighted, physically consistent.

Gauss–Newton on the weighted residuals (H_ij − ℓ_iᵀ M(θ)⁻¹ w_j)/σ_ij, where
σ_ij is each massline's 1-σ from its band fit (the data's own scatter),
started from the paper's method 3 (or the plate's eqs. 10–13). A body must
have a positive definite pseudo-inertia matrix (Wensing, Kim & Slotine 2017)

    P(θ) = [[½ tr(J_O) I − J_O, m c], [m cᵀ, m]] ≻ 0,

linear in θ; when a step leaves that cone it is taken again as the
least-squares step subject to P ⪰ ε I, solved with cvxpy.

The covariance is the inverse information at the solution, scaled up by the
reduced χ² when the residuals are larger than the band fits said (model
errors such as transverse sensitivity show up that way).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.placement.information import sensitivities
from massline.placement.likelihood import starting_body
from massline.placement.masslines import Masslines
from massline.placement.model import RigidModel
from massline.placement.rigid_body import RigidBody, tensor_from_six

CONSISTENCY_MARGIN = 1e-9  # smallest eigenvalue of P kept, relative to m L²


@dataclass(frozen=True, eq=False)
class Estimate:
    """The weighted estimate.

    Attributes
    ----------
    body : RigidBody
        Identified mass, CoG and inertia about the CoG (test frame, SI).
    model : RigidModel
        The parameterisation at the estimate (scaled parameters, planar or not).
    covariance : (p, p) array
        Covariance of the scaled parameters θ̃.
    chi2 : float
        Reduced χ² of the weighted residuals (≈ 1 when the band fits' σ explain them).
    residual : (n_s, n_e) array
        H_measured − H_model, (m/s²)/N.
    constrained : bool
        Whether the physical-consistency constraint was active.
    """

    body: RigidBody
    model: RigidModel
    covariance: np.ndarray
    chi2: float
    residual: np.ndarray
    constrained: bool


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
    """argmin ‖J δ − r‖² subject to P(θ + scale·δ) ⪰ ε I (δ in scaled parameters)."""
    import cvxpy as cp

    delta = cp.Variable(model.p)
    P = sum(pseudo_inertia(np.eye(10)[k] * model.scale[k]) * delta[k] for k in range(model.p))
    P = P + pseudo_inertia(theta)
    epsilon = CONSISTENCY_MARGIN * model.scale[-1]
    problem = cp.Problem(cp.Minimize(cp.sum_squares(J @ delta - r)), [(P + P.T) / 2 >> epsilon * np.eye(4)])
    problem.solve(solver=cp.SCS, eps=1e-10, max_iters=20000)
    return np.asarray(delta.value)


def estimate(data: Masslines, sigma: np.ndarray, planar: bool = False, iterations: int = 30) -> Estimate:
    """Weighted, consistent least squares of all masslines; σ (n_s, n_e) in (m/s²)/N."""
    model = RigidModel(starting_body(data, planar), planar)
    s, e = model.coordinates(data.sensors), model.coordinates(data.exciters)
    theta, constrained = model.theta, False
    for _ in range(iterations):
        G, H = sensitivities(model, s, e)
        J = (G / sigma[:, :, None]).reshape(-1, model.p)
        r = ((data.values - H) / sigma).ravel()
        step = np.linalg.lstsq(J, r, rcond=None)[0]
        candidate = theta + model.scale * step
        if not planar and not is_consistent(candidate, model.scale[-1]):
            step, constrained = constrained_step(J, r, theta, model), True
            candidate = theta + model.scale * step
        theta = candidate
        model = RigidModel(model.body(theta), planar)
        if np.abs(step).max() < 1e-12:
            break
    G, H = sensitivities(model, s, e)
    J = (G / sigma[:, :, None]).reshape(-1, model.p)
    residual = data.values - H
    dof = max(residual.size - model.p, 1)
    chi2 = float(np.sum((residual / sigma) ** 2) / dof)
    covariance = np.linalg.inv(J.T @ J) * max(chi2, 1.0)
    return Estimate(model.nominal, model, covariance, chi2, residual, constrained)
