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
from functools import cached_property

import numpy as np

from massline.placement.errors import MasslineError
from massline.placement.information import sensitivities
from massline.placement.masslines import Masslines
from massline.placement.methods import starting_body
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
        Reduced χ² of the weighted residuals (≈ 1 when the band fits' σ explain them; nan with no redundancy).
    dof : float
        The degrees of freedom χ² is reduced by: masslines less the parameters the data pay for.
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
    dof: float
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


@dataclass(frozen=True, eq=False)
class WeightedSystem:
    """The weighted Gauss–Newton system at one iterate, kept in its block form.

    ``A`` (n_s, n_e, p): ∂H_ij/∂θ̃ / σ_ij; ``D`` (n_s, n_e, 2) or None: ∂H_ij/∂τ_i / σ_ij;
    ``r`` (n_s, n_e): (H_ij − model) / σ_ij; ``prior`` (n_s, 2): the prior rows' residual −τ_i/t.
    """

    A: np.ndarray
    D: np.ndarray | None
    r: np.ndarray
    prior: np.ndarray
    transverse: float

    @property
    def chi2_sum(self) -> float:
        return float(np.sum(self.r**2) + np.sum(self.prior**2))

    @cached_property
    def eliminated(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """θ̃'s information S with the τ_i eliminated, each Cᵢ⁻¹ (n_s, 2, 2) and Eᵢ = AᵢᵀDᵢ (n_s, p, 2).

        Normal equations [[Σ AᵢᵀAᵢ, Eᵢ], [Eᵢᵀ, Cᵢ]] with Cᵢ = DᵢᵀDᵢ + I/t²: the Schur complement
        S = Σ AᵢᵀAᵢ − Eᵢ Cᵢ⁻¹ Eᵢᵀ, in O(n_s) work (Cᵢ⁻¹ and Eᵢ empty without transverse readings).
        """
        S = np.tensordot(self.A, self.A, axes=([0, 1], [0, 1]))
        if self.D is None:
            return S, np.zeros((len(self.r), 0, 0)), np.zeros((len(self.r), S.shape[0], 0))
        C_inv = np.linalg.inv(np.swapaxes(self.D, 1, 2) @ self.D + np.eye(2) / self.transverse**2)
        E = np.swapaxes(self.A, 1, 2) @ self.D
        return S - np.tensordot(E @ C_inv, E, axes=([0, 2], [0, 2])), C_inv, E

    def step(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Gauss–Newton step (θ̃, τ) and the information S of θ̃ (:attr:`eliminated`)."""
        S, C_inv, E = self.eliminated
        b = np.tensordot(self.A, self.r, axes=([0, 1], [0, 1]))
        if self.D is None:
            return np.linalg.solve(S, b), np.zeros((len(self.r), 0)), S
        g = np.einsum("ijk,ij->ik", self.D, self.r) + self.prior / self.transverse
        x = np.linalg.solve(S, b - np.tensordot(E @ C_inv, g, axes=([0, 2], [0, 1])))
        tau = (C_inv @ (g - np.einsum("ipk,p->ik", E, x))[..., None])[..., 0]
        return x, tau, S

    def paid_parameters(self) -> float:
        """p_eff = tr(J_d (JᵀJ)⁻¹ J_dᵀ), J_d the masslines' rows of the Jacobian J: the parameters the data pay for.

        From the blocks, with N = JᵀJ = J_dᵀJ_d + diag(0, I/t²): p_eff = p + 2n_s − tr(N⁻¹_ττ)/t², and
        N⁻¹'s τ_i block is Cᵢ⁻¹ + Cᵢ⁻¹EᵢᵀS⁻¹EᵢCᵢ⁻¹, so p_eff = p + Σ tr(Cᵢ⁻¹DᵢᵀDᵢ) − tr(S⁻¹ Σ EᵢCᵢ⁻²Eᵢᵀ)/t².
        Raises LinAlgError when S is singular.
        """
        S, C_inv, E = self.eliminated
        S_inv = np.linalg.inv(S)
        if self.D is None:
            return float(len(S))
        seen = np.sum((self.D @ C_inv) * self.D)
        F = E @ C_inv
        shared = np.tensordot(F, F, axes=([0, 2], [0, 2]))
        return len(S) + float(seen) - float(np.trace(S_inv @ shared)) / self.transverse**2

    def dense(self) -> tuple[np.ndarray, np.ndarray]:
        """The whole Jacobian and residual, prior rows included (for the constrained step)."""
        n_s, n_e, p = self.A.shape
        rows, residual = [self.A.reshape(-1, p)], [self.r.ravel()]
        if self.D is not None:
            block = np.zeros((n_s, n_e, n_s, 2))
            block[np.arange(n_s), :, np.arange(n_s)] = self.D
            rows = [np.hstack([rows[0], block.reshape(n_s * n_e, 2 * n_s)])]
            rows.append(np.hstack([np.zeros((2 * n_s, p)), np.eye(2 * n_s) / self.transverse]))
            residual.append(self.prior.ravel())
        return np.vstack(rows), np.concatenate(residual)


def transverse_lines(points: np.ndarray, T: np.ndarray) -> np.ndarray:
    """(t_k, r_i × t_k) (n_s, 6, 2): the line coordinates of each channel's transverse axes T_i at its point r_i."""
    return np.concatenate([T, np.cross(points[:, :, None], T, axis=1)], axis=1)


def weighted_system(model, s, e, data, sigma, lines, tilt, transverse) -> tuple[WeightedSystem, np.ndarray]:
    """The weighted system and the model's masslines H.

    A sensor reading (d_i + T_i τ_i)·a(r_i) has line coordinates (d', r_i × d') = s_i + L_i τ_i, with
    L_i = ``lines`` (:func:`transverse_lines`), so ∂H_ij/∂τ_i = L_iᵀ M⁻¹ w_j; the prior
    τ_ik ~ N(0, transverse²) adds the rows τ_ik / transverse.
    """
    G, H = sensitivities(model, s, e)
    D = None
    if lines is not None:
        D = (e @ model.mass_matrix_inverse) @ lines / sigma[:, :, None]
    system = WeightedSystem(G / sigma[:, :, None], D, (data - H) / sigma, -tilt / max(transverse, 1e-300), transverse)
    return system, H


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
    lines = None if T is None else transverse_lines(points, T)
    tilt = np.zeros((len(directions), 0 if T is None else 2))
    theta, constrained = model.theta, False
    for _ in range(iterations):
        s = s0 if T is None else s0 + (lines @ tilt[:, :, None])[:, :, 0]
        system, _ = weighted_system(model, s, e, data.values, sigma, lines, tilt, transverse)
        x, tau, _ = system.step()
        candidate = theta + model.scale * x
        if not np.all(np.isfinite(candidate)):
            raise MasslineError(
                "the estimate diverged: the masslines fit no rigid body (a flipped or swapped channel, or a band "
                "across a resonance?); run massline diagnose, or give --band LO HI"
            )
        if not planar and not is_consistent(candidate, model.scale[-1]):
            step = constrained_step(*system.dense(), theta, model)
            x, tau, constrained = step[: model.p], step[model.p :].reshape(tilt.shape), True
            candidate = theta + model.scale * x
        theta, tilt = candidate, tilt + tau
        model = RigidModel(model.body(theta), planar)
        if max(np.abs(x).max(), np.abs(tau).max(initial=0.0)) < 1e-12:
            break
    s = s0 if T is None else s0 + (lines @ tilt[:, :, None])[:, :, 0]
    system, H = weighted_system(model, s, e, data.values, sigma, lines, tilt, transverse)
    chi2, dof = reduced_chi2(system)
    covariance = np.linalg.inv(system.step()[2]) * (max(chi2, 1.0) if np.isfinite(chi2) else 1.0)
    readings = np.zeros_like(directions) if T is None else np.einsum("nak,nk->na", T, tilt)
    prior = 0.0 if T is None else transverse
    return Estimate(model.nominal, model, covariance, chi2, dof, data.values - H, constrained, readings, prior)


def reduced_chi2(system: WeightedSystem) -> tuple[float, float]:
    """Σ r_ij² / (n − p_eff) over the masslines, and n − p_eff: ≈ 1 when the band fits' σ explain the residuals.

    p_eff = tr(J_d (JᵀJ)⁻¹ J_dᵀ) counts the parameters the data pay for: the properties and as much of
    each channel's transverse reading as the data, not the prior, determine. Counting the two transverse
    components of every channel in full (or not at all) makes χ² too small on a layout with few hits per
    channel. χ² is nan when nothing is left over to judge the fit by (no redundancy).
    """
    n = system.r.size
    try:
        paid = system.paid_parameters()
    except np.linalg.LinAlgError:
        return np.nan, 0.0
    left = n - paid
    return (float(np.sum(system.r**2) / left) if left > 0.5 else np.nan), max(left, 0.0)
