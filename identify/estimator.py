"""The best estimator: all masslines at once, weighted, physically consistent.

Gauss–Newton on the weighted residuals (H_ij − ℓ_iᵀ M(θ)⁻¹ w_j)/σ_ij, where
σ_ij is each massline's 1-σ from its band fit (the data's own scatter),
started from the paper's method 3 (or the plate's eqs. 10–13). A body must
have a positive definite pseudo-inertia matrix (Wensing, Kim & Slotine 2017)

    P(θ) = [[½ tr(J_O) I − J_O, m c], [m cᵀ, m]] ≻ 0,

linear in θ; when a step leaves that cone it is taken again as the
least-squares step subject to P ⪰ ε I, solved with cvxpy.

Accelerometers read a few per cent across their axis (transverse sensitivity,
mounting misalignment: indistinguishable in the data). Each channel's two
transverse components are estimated with θ under a Gaussian prior of the
datasheet's size; with several exciters per sensor they are well determined,
and leaving them out biases the properties by several per cent.

The covariance is the inverse information at the solution (data and prior),
scaled up by the reduced χ² when the residuals are larger than the band fits
said.
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
TRANSVERSE = 0.03  # prior 1-σ of an accelerometer's transverse sensitivity (datasheets: 3–5 %, paper §3)


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
    transverse : (n_s, 3) array
        Each channel's estimated transverse reading (the part of its reading vector ⊥ its axis).
    prior : float
        The transverse-sensitivity prior used (0: axes taken as exact).
    """

    body: RigidBody
    model: RigidModel
    covariance: np.ndarray
    chi2: float
    residual: np.ndarray
    constrained: bool
    transverse: np.ndarray
    prior: float


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
    problem.solve(solver=cp.CLARABEL)
    return np.asarray(delta.value)


def perpendicular_bases(directions: np.ndarray) -> np.ndarray:
    """T_i (n, 3, 2): two unit vectors ⊥ each direction d_i, the axes a sensor's transverse reading lies on."""
    helper = np.eye(3)[np.argmin(np.abs(directions), axis=1)]
    t1 = np.cross(directions, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(directions, t1)], axis=2)


def weighted_system(model, s, e, data, sigma, T, points, tilt, transverse):
    """Jacobian and residual of the weighted masslines, with the transverse readings' prior rows.

    A sensor reading (d_i + T_i τ_i)·a(r_i) has line coordinates (d', r_i × d'), linear in
    τ_i, so ∂H_ij/∂τ_ik = (t_k, r_i × t_k)ᵀ M⁻¹ w_j; the prior τ_ik ~ N(0, transverse²)
    adds the rows τ_ik / transverse.
    """
    G, H = sensitivities(model, s, e)
    rows = [(G / sigma[:, :, None]).reshape(-1, model.p)]
    residual = [((data - H) / sigma).ravel()]
    if T is not None:
        n_s, n_e = H.shape
        lines = np.concatenate([T, np.cross(points[:, :, None], T, axis=1)], axis=1)  # (n_s, 6, 2)
        V = np.linalg.solve(model.mass_matrix(model.theta), e.T)
        D = np.einsum("nak,aj->njk", lines, V) / sigma[:, :, None]  # (n_s, n_e, 2)
        block = np.zeros((n_s, n_e, n_s, 2))
        block[np.arange(n_s), :, np.arange(n_s)] = D
        rows = [np.hstack([rows[0], block.reshape(n_s * n_e, 2 * n_s)])]
        rows.append(np.hstack([np.zeros((2 * n_s, model.p)), np.eye(2 * n_s) / transverse]))
        residual.append(-tilt.ravel() / transverse)
    return np.vstack(rows), np.concatenate(residual), H


def estimate(
    data: Masslines, sigma: np.ndarray, planar: bool = False, transverse: float = TRANSVERSE, iterations: int = 40
) -> Estimate:
    """Weighted, consistent least squares of all masslines; σ (n_s, n_e) in (m/s²)/N.

    ``transverse``: 1-σ of each accelerometer's transverse sensitivity (fraction; mounting
    misalignment reads the same way). The two transverse components τ_i of every channel
    are estimated with the properties, under that prior; 0 takes the axes as exact.
    Plate data (§2.3) use exact axes: a plate's z-lines have no in-plane reading to model.
    """
    model = RigidModel(starting_body(data, planar), planar)
    s0, e = model.coordinates(data.sensors), model.coordinates(data.exciters)
    points, directions = data.sensors.points, data.sensors.directions
    T = None if planar or transverse <= 0 else perpendicular_bases(directions)
    tilt = np.zeros((len(directions), 2))
    theta, constrained = model.theta, False
    for _ in range(iterations):
        s = s0 if T is None else _coordinates(points, directions + np.einsum("nak,nk->na", T, tilt))
        J, r, _ = weighted_system(model, s, e, data.values, sigma, T, points, tilt, transverse)
        step = np.linalg.lstsq(J, r, rcond=None)[0]
        candidate = theta + model.scale * step[: model.p]
        if not planar and not is_consistent(candidate, model.scale[-1]):
            step, constrained = constrained_step(J, r, theta, model), True
            candidate = theta + model.scale * step[: model.p]
        theta = candidate
        tilt = tilt + step[model.p :].reshape(tilt.shape) if T is not None else tilt
        model = RigidModel(model.body(theta), planar)
        if np.abs(step).max() < 1e-12:
            break
    s = s0 if T is None else _coordinates(points, directions + np.einsum("nak,nk->na", T, tilt))
    J, r, H = weighted_system(model, s, e, data.values, sigma, T, points, tilt, transverse)
    chi2 = float(r @ r / max(data.values.size - model.p, 1))
    covariance = np.linalg.inv(J.T @ J)[: model.p, : model.p] * max(chi2, 1.0)
    readings = np.zeros_like(directions) if T is None else np.einsum("nak,nk->na", T, tilt)
    prior = 0.0 if T is None else transverse
    return Estimate(model.nominal, model, covariance, chi2, data.values - H, constrained, readings, prior)


def _coordinates(points: np.ndarray, readings: np.ndarray) -> np.ndarray:
    """Line coordinates (d, r × d) of unnormalised reading vectors d (a gain stays a gain)."""
    return np.hstack([readings, np.cross(points, readings)])
