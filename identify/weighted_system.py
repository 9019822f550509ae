"""The weighted Gauss–Newton system of the best estimator (:mod:`.estimator`): what every iterate shares
(:class:`WeightedProblem`: the masslines, their 1-σ, the lines and the priors) and the system at one iterate
(:class:`WeightedSystem`), kept in its block form.

The residuals are (H_ij − ℓ_iᵀ M(θ)⁻¹ w_j)/σ_ij over the masslines, the scale's reading (m_W − m)/σ_W when
weighed, and the prior rows τ_ik/t of each channel's two transverse components.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from massline.core.information import driven, sensitivities
from massline.core.lines import transverse_lines
from massline.core.uncertainty_budget import dense_jacobian
from massline.core.masslines import Masslines
from massline.core.model import RigidModel
from massline.identify.weighing import WeighedMass


@dataclass(frozen=True, eq=False)
class WeightedSystem:
    """The weighted Gauss–Newton system at one iterate, kept in its block form.

    ``A`` (n_s, n_e, p): ∂H_ij/∂θ̃ / σ_ij; ``D`` (n_s, n_e, 2) or None: ∂H_ij/∂τ_i / σ_ij;
    ``r`` (n_s, n_e): (H_ij − model) / σ_ij; ``prior`` (n_s, 2): the prior rows' residual −τ_i/t;
    ``scale_row`` (p,) or None: the scale's row ∂m/∂θ̃ / σ_W, and ``scale_r`` its residual (m_W − m)/σ_W;
    ``present``: how many masslines have a finite σ (a missing pair's σ is inf: a row of zeros), None for all.
    """

    A: np.ndarray
    D: np.ndarray | None
    r: np.ndarray
    prior: np.ndarray
    transverse: float
    scale_row: np.ndarray | None = None
    scale_r: float = 0.0
    present: int | None = None

    @property
    def count(self) -> int:
        """How many measured rows carry weight: the masslines present (``present``; all when None), the scale's."""
        masslines = self.r.size if self.present is None else self.present
        return masslines + (self.scale_row is not None)

    @property
    def measured(self) -> np.ndarray:
        """The measured rows' residuals: every massline's, then the scale's (when weighed)."""
        return np.append(self.r.ravel(), [] if self.scale_row is None else [self.scale_r])

    @property
    def chi2_sum(self) -> float:
        return float(np.sum(self.measured**2) + np.sum(self.prior**2))

    @cached_property
    def eliminated(self) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, np.ndarray | None]:
        """θ̃'s information S with the τ_i eliminated; each sensor's orthogonal Qᵢ, triangular Rᵢ and rows Ãᵢ.

        Sensor i's rows [[Aᵢ, Dᵢ], [0, I/t]] (its masslines, then its prior rows) are turned by the Qᵢ of a QR
        [Dᵢ; I/t] = Qᵢ [Rᵢ; 0] ((n_e + 2) × 2): the first two rows then hold τ_i, which they fit exactly, and
        the other n_e rows Ãᵢ = Qᵢ[:, 2:]ᵀ [Aᵢ; 0] θ̃ alone, so S = Σ ÃᵢᵀÃᵢ + aaᵀ (a the scale's row, θ̃
        only; none without a reading), in O(n_s) work. S equals Σ AᵢᵀAᵢ + aaᵀ − AᵢᵀDᵢCᵢ⁻¹DᵢᵀAᵢ with
        Cᵢ = DᵢᵀDᵢ + I/t², without that difference's cancellation (S is a hundredth of Σ AᵢᵀAᵢ on a layout
        whose masslines the transverse readings nearly absorb). Qᵢ, Rᵢ, Ãᵢ are None without transverse readings.
        """
        if self.D is None:
            S, Q, R, A = np.tensordot(self.A, self.A, axes=([0, 1], [0, 1])), None, None, None
        else:
            n_s, n_e, _ = self.A.shape
            prior = np.broadcast_to(np.eye(2) / self.transverse, (n_s, 2, 2))
            Q, R = np.linalg.qr(np.concatenate([self.D, prior], axis=1), mode="complete")
            A = np.swapaxes(Q[:, :n_e, 2:], 1, 2) @ self.A  # (n_s, n_e, p)
            S, R = np.tensordot(A, A, axes=([0, 1], [0, 1])), R[:, :2]
        if self.scale_row is not None:
            S = S + np.outer(self.scale_row, self.scale_row)
        return S, Q, R, A

    def step(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Gauss–Newton step (θ̃, τ) and the information S of θ̃ (:attr:`eliminated`)."""
        S, Q, R, A = self.eliminated
        b = 0.0 if self.scale_row is None else self.scale_row * self.scale_r
        if self.D is None:
            b = b + np.tensordot(self.A, self.r, axes=([0, 1], [0, 1]))
            return np.linalg.solve(S, b), np.zeros((len(self.r), 0)), S
        n_e = self.A.shape[1]
        turned = (np.swapaxes(Q, 1, 2) @ np.concatenate([self.r, self.prior], axis=1)[..., None])[..., 0]
        x = np.linalg.solve(S, np.tensordot(A, turned[:, 2:], axes=([0, 1], [0, 1])) + b)
        fitted = (np.swapaxes(Q[:, :n_e, :2], 1, 2) @ (self.A @ x)[..., None])[..., 0]
        tau = np.linalg.solve(R, (turned[:, :2] - fitted)[..., None])[..., 0]
        return x, tau, S

    def paid_parameters(self) -> float:
        """p_eff = tr(J_d (JᵀJ)⁻¹ J_dᵀ), J_d the measured rows of the Jacobian J (the masslines and the scale's):
        the parameters the data pay for, the sum of the measured rows' leverages.

        In the rows turned by the Qᵢ (:attr:`eliminated`) the hat matrix is I on each sensor's two τ rows plus
        [Ã; a] S⁻¹ [Ã; a]ᵀ, so sensor i's masslines (the first n_e rows of Qᵢ) pay ‖Qᵢ[:n_e, :2]‖² +
        tr(S⁻¹ MᵢᵀMᵢ) with Mᵢ = Qᵢ[:n_e, 2:] Ãᵢ, and the scale's row aᵀS⁻¹a. Raises LinAlgError when S is
        singular.
        """
        S, Q, _, A = self.eliminated
        if self.D is None:
            np.linalg.inv(S)  # raises when S is singular
            return float(len(S))
        n_e = self.A.shape[1]
        M = Q[:, :n_e, 2:] @ A
        W = np.tensordot(M, M, axes=([0, 1], [0, 1]))
        if self.scale_row is not None:
            W = W + np.outer(self.scale_row, self.scale_row)
        return float(np.sum(Q[:, :n_e, :2] ** 2)) + float(np.trace(np.linalg.solve(S, W)))

    def scale_leverage(self) -> float:
        """The scale row's leverage h = aᵀ(N⁻¹)_θθ a = aᵀS⁻¹a (nan without a reading); LinAlgError when S is singular."""
        if self.scale_row is None:
            return np.nan
        return float(self.scale_row @ np.linalg.solve(self.eliminated[0], self.scale_row))

    def dense(self) -> tuple[np.ndarray, np.ndarray]:
        """The whole Jacobian and residual: the measured rows first (masslines, then the scale), then the priors."""
        J = dense_jacobian(self.A, self.D, self.transverse, self.scale_row)
        residual = [self.measured] + ([] if self.D is None else [self.prior.ravel()])
        return J, np.concatenate(residual)


def weighted_system(
    model, s, e, data, sigma, *, lines, tilt, transverse, weighed=None, riding=None
) -> tuple[WeightedSystem, np.ndarray]:
    """The weighted system and the model's masslines H.

    A sensor reading (d_i + T_i τ_i)·a(r_i) has line coordinates (d', r_i × d') = s_i + L_i τ_i, with
    L_i = ``lines`` (:func:`transverse_lines`), so ∂H_ij/∂τ_i = L_iᵀ M⁻¹ w_j; the prior
    τ_ik ~ N(0, transverse²) adds the rows τ_ik / transverse. A scale reading adds the row
    (m_W − θ_0)/σ_W, with ∂θ_0/∂θ̃_0 = m₀ (the model's mass scale) its only non-zero derivative. ``riding``
    (n_e, p): the mass riding at each exciter (:class:`.estimator.Estimate`).
    """
    G, H = sensitivities(model, s, e, riding)
    D = None
    if lines is not None:
        D = driven(model, e, riding) @ lines / sigma[:, :, None]
    scale = {}
    if weighed is not None:
        row = np.eye(model.p)[0] * model.scale[0] / weighed.sd
        scale = {"scale_row": row, "scale_r": (weighed.mass - model.theta[0]) / weighed.sd}
    prior = -tilt / max(transverse, 1e-300)
    present = int(np.isfinite(sigma).sum())
    system = WeightedSystem(G / sigma[:, :, None], D, (data - H) / sigma, prior, transverse, present=present, **scale)
    return system, H


class Iterate(NamedTuple):
    """One Gauss–Newton iterate: the model re-centred at its body, its weighted system, the model's masslines
    H (n_s, n_e), (m/s²)/N, and each channel's transverse reading τ_i (n_s, 2), or (n_s, 0) with exact axes."""

    model: RigidModel
    system: WeightedSystem
    masslines: np.ndarray
    tilt: np.ndarray


@dataclass(frozen=True, eq=False, kw_only=True)
class WeightedProblem:
    """What the weighted system of every iterate shares.

    Attributes
    ----------
    data : Masslines
        The measured masslines H_ij (n_s, n_e), (m/s²)/N, on their sensor and exciter lines.
    sigma : (n_s, n_e) array
        Each massline's 1-σ, (m/s²)/N; inf at a missing pair (a row of zeros).
    planar : bool
        Plate data (§2.3): the plate's 6 parameters on (a_z, α_x, α_y).
    sensors, exciters : (n_s, q), (n_e, q) arrays
        The lines' coordinates in the model (:meth:`RigidModel.coordinates`).
    axes : (n_s, 3, 2) array or None
        Each channel's transverse axes T_i (:func:`massline.core.lines.perpendicular_bases`); None: the axes taken as exact.
    transverse : float
        The prior 1-σ t of each transverse component τ_ik (a fraction of the axial reading).
    weighed : WeighedMass or None
        A scale's reading of the body as tested, kg: one more measured row.
    riding : (n_e, p) array or None
        SI parameters of the mass riding at each exciter's point while it drives (a force gauge's structure side).
    """

    data: Masslines
    sigma: np.ndarray
    planar: bool
    sensors: np.ndarray
    exciters: np.ndarray
    axes: np.ndarray | None
    transverse: float
    weighed: WeighedMass | None = None
    riding: np.ndarray | None = None

    @cached_property
    def lines(self) -> np.ndarray | None:
        """L_i (n_s, 6, 2): the line coordinates of each channel's transverse axes (:func:`transverse_lines`)."""
        return None if self.axes is None else transverse_lines(self.data.sensors.points, self.axes)

    @property
    def untilted(self) -> np.ndarray:
        """τ = 0 (n_s, 2), or (n_s, 0) with exact axes: every channel read along its axis."""
        return np.zeros((len(self.data.sensors.directions), 0 if self.axes is None else 2))

    def on(self, model: RigidModel, tilt: np.ndarray) -> Iterate:
        """``model``'s weighted system and masslines with the channels tilted by ``tilt`` τ (n_s, 2)."""
        s = self.sensors if self.axes is None else self.sensors + (self.lines @ tilt[:, :, None])[:, :, 0]
        system, H = weighted_system(
            model, s, self.exciters, self.data.values, self.sigma, lines=self.lines, tilt=tilt,
            transverse=self.transverse, weighed=self.weighed, riding=self.riding,
        )
        return Iterate(model, system, H, tilt)

    def at(self, model: RigidModel, theta: np.ndarray, tilt: np.ndarray) -> Iterate:
        """:meth:`on` the model re-centred at the SI parameters θ (a plate's unobserved entries kept from
        ``model``'s body); MasslineError (a ValueError) where θ is no body (a mass ≤ 0)."""
        return self.on(RigidModel(model.body(theta), self.planar), tilt)
