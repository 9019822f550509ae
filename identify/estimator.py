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

A scale's reading of the body (``weighed``, :mod:`.weighing`) is one more
measured row (m_W − m)/σ_W beside the masslines: it adds (∂m/∂θ)(∂m/∂θ)ᵀ/σ_W²
to the information, so a known mass sharpens the CoG and the inertia too.

The covariance is the inverse information at the solution (data and priors),
scaled up by the reduced χ² when the residuals are larger than the band fits
and the scale said.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from massline.identify.weighing import WeighedMass
from massline.core.band import GIVE_BAND
from massline.core.errors import MasslineError
from massline.core.information import driven, sensitivities
from massline.core.lines import cross
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.identify.consistency import constrained_step, is_consistent
from massline.identify.missing_pairs import completed
from massline.core.rigid_body import RigidBody

DIVERGED = (
    "the estimate diverged: the masslines fit no rigid body (a flipped or swapped channel, or a band across a "
    f"resonance?); run massline diagnose, or give {GIVE_BAND}"
)
TRANSVERSE = 0.03  # prior 1-σ of an accelerometer's transverse sensitivity (datasheets: 3–5 %, paper §3)


@dataclass(frozen=True, eq=False, kw_only=True)
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
    weighed : WeighedMass or None
        The scale's reading of the body as tested (kg), used as a measured row; None without one.
    weighed_z : float
        That row's studentised residual (m_W − m)/(σ_W √(1 − h)), h its leverage: how many σ the scale and the
        masslines disagree by (nan without a reading, or when the masslines do not see the mass at all).
    riding : (n_e, p) array or None
        SI parameters of the mass riding at each exciter's point while it drives (a force gauge's structure
        side): column j's masslines are those of ``body`` plus it (``core.information.sensitivities``).
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
    weighed: WeighedMass | None = None
    weighed_z: float = np.nan
    riding: np.ndarray | None = None


def perpendicular_bases(directions: np.ndarray) -> np.ndarray:
    """T_i (n, 3, 2): two unit vectors ⊥ each direction d_i, the axes a sensor's transverse reading lies on."""
    helper = np.eye(3)[np.argmin(np.abs(directions), axis=1)]
    t1 = cross(directions, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, cross(directions, t1)], axis=2)


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
        n_s, n_e, p = self.A.shape
        width = p + (0 if self.D is None else 2 * n_s)
        rows = [self.A.reshape(-1, p)]
        if self.D is not None:
            block = np.zeros((n_s, n_e, n_s, 2))
            block[np.arange(n_s), :, np.arange(n_s)] = self.D
            rows = [np.hstack([rows[0], block.reshape(n_s * n_e, 2 * n_s)])]
        if self.scale_row is not None:
            rows.append(np.pad(self.scale_row, (0, width - p))[None, :])
        residual = [self.measured]
        if self.D is not None:
            rows.append(np.hstack([np.zeros((2 * n_s, p)), np.eye(2 * n_s) / self.transverse]))
            residual.append(self.prior.ravel())
        return np.vstack(rows), np.concatenate(residual)


def transverse_lines(points: np.ndarray, T: np.ndarray) -> np.ndarray:
    """(t_k, r_i × t_k) (n_s, 6, 2): the line coordinates of each channel's transverse axes T_i at its point r_i."""
    return np.concatenate([T, np.cross(points[:, :, None], T, axis=1)], axis=1)


def weighted_system(
    model, s, e, data, sigma, *, lines, tilt, transverse, weighed=None, riding=None
) -> tuple[WeightedSystem, np.ndarray]:
    """The weighted system and the model's masslines H.

    A sensor reading (d_i + T_i τ_i)·a(r_i) has line coordinates (d', r_i × d') = s_i + L_i τ_i, with
    L_i = ``lines`` (:func:`transverse_lines`), so ∂H_ij/∂τ_i = L_iᵀ M⁻¹ w_j; the prior
    τ_ik ~ N(0, transverse²) adds the rows τ_ik / transverse. A scale reading adds the row
    (m_W − θ_0)/σ_W, with ∂θ_0/∂θ̃_0 = m₀ (the model's mass scale) its only non-zero derivative. ``riding``
    (n_e, p): the mass riding at each exciter (:class:`Estimate`).
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


def damped(trial, theta, dtheta, tilt, dtilt, before: float, halvings: int = 40):
    """(h, trial(θ + h Δθ, τ + h Δτ)) for the first h of 1, ½, ¼, … whose system's objective Σr² is at most
    ``before`` (finite); ``trial`` gives (model, system, …) at the parameters θ (SI) and tilts τ.

    Gauss–Newton's full step overshoots where the masslines fit no rigid body (a band across a resonance, a
    flipped channel): the iterate can run to a mass of 10¹⁹ kg and a singular system. Halving the step until the
    objective does not rise keeps every iterate a body and the objective falling. None when no h does.
    """
    h = 1.0
    for _ in range(halvings):
        try:
            found = trial(theta + h * dtheta, tilt + h * dtilt)
        except (np.linalg.LinAlgError, FloatingPointError, ValueError, ZeroDivisionError):
            found = None
        if found is not None and np.isfinite(found[1].chi2_sum) and found[1].chi2_sum <= before * (1 + 1e-12):
            return h, found
        h /= 2
    return None


def estimate(
    data: Masslines,
    sigma: np.ndarray,
    planar: bool = False,
    transverse: float = TRANSVERSE,
    iterations: int = 40,
    weighed: WeighedMass | None = None,
    riding: np.ndarray | None = None,
) -> Estimate:
    """Weighted, consistent least squares of all masslines; σ (n_s, n_e) in (m/s²)/N.

    ``transverse``: 1-σ of each accelerometer's transverse sensitivity (fraction; mounting
    misalignment reads the same way). The two transverse components τ_i of every channel
    are estimated with the properties, under that prior; 0 takes the axes as exact.
    Plate data (§2.3) use exact axes: a plate's z-lines have no in-plane reading to model.
    ``weighed``: a scale's reading of the body as tested (with whatever the masslines weigh on it).
    ``riding`` (n_e, p), SI: a mass riding at each exciter's point while it drives (force gauges; the body
    estimated is then the one without them, mass cancellation by the model).
    """
    present = np.isfinite(sigma)
    start = data if present.all() else completed(data, present, planar)  # a missing pair: σ = inf, no weight
    model = RigidModel(starting_body(start, planar), planar)
    s0, e = model.coordinates(data.sensors), model.coordinates(data.exciters)
    points, directions = data.sensors.points, data.sensors.directions
    T = None if planar or transverse <= 0 else perpendicular_bases(directions)
    lines = None if T is None else transverse_lines(points, T)
    tilt = np.zeros((len(directions), 0 if T is None else 2))
    constrained = False

    def at(theta: np.ndarray, tilt: np.ndarray) -> tuple[RigidModel, WeightedSystem, np.ndarray, np.ndarray]:
        """The model re-centred at θ, its weighted system and masslines with the channels tilted by ``tilt``;
        MasslineError (a ValueError) where θ is no body (a mass ≤ 0)."""
        return on(RigidModel(model.body(theta), planar), tilt)

    def on(moved: RigidModel, tilt: np.ndarray) -> tuple[RigidModel, WeightedSystem, np.ndarray, np.ndarray]:
        """``moved``'s weighted system and masslines with the channels tilted by ``tilt``."""
        s = s0 if T is None else s0 + (lines @ tilt[:, :, None])[:, :, 0]
        system, H = weighted_system(
            moved, s, e, data.values, sigma, lines=lines, tilt=tilt, transverse=transverse, weighed=weighed,
            riding=riding,
        )
        return moved, system, H, tilt

    model, system, H, tilt = on(model, tilt)  # the start as given (θ → body loses J_G's digits far from O)
    for _ in range(iterations):
        try:
            x, tau, _ = system.step()
        except np.linalg.LinAlgError:  # S singular: no step
            raise MasslineError(DIVERGED) from None
        theta = model.theta
        if np.all(np.isfinite(x)) and not planar and not is_consistent(theta + model.scale * x, model.scale[-1]):
            step = constrained_step(*system.dense(), theta, model)
            x, tau, constrained = step[: model.p], step[model.p :].reshape(tilt.shape), True
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(tau))):
            raise MasslineError(DIVERGED)
        # from an inconsistent start the (constrained) full step is the way back to a body: taken whole
        ceiling = np.inf if not (planar or is_consistent(theta, model.scale[-1])) else system.chi2_sum
        taken = damped(at, theta, model.scale * x, tilt, tau, ceiling)
        if taken is None:  # no step along (x, τ) lowers the objective: as far as Gauss–Newton goes
            break
        h, (model, system, H, tilt) = taken
        if h * max(np.abs(x).max(), np.abs(tau).max(initial=0.0)) < 1e-12:
            break
    chi2, dof, leverage = reduced_chi2(system)
    covariance = np.linalg.inv(system.step()[2]) * (max(chi2, 1.0) if np.isfinite(chi2) else 1.0)
    readings = np.zeros_like(directions) if T is None else np.einsum("nak,nk->na", T, tilt)
    prior = 0.0 if T is None else transverse
    z = studentised(system.scale_r, leverage) if weighed is not None else np.nan
    return Estimate(
        body=model.nominal,
        model=model,
        covariance=covariance,
        chi2=chi2,
        dof=dof,
        residual=np.where(present, data.values - H, np.nan),
        constrained=constrained,
        transverse=readings,
        prior=prior,
        weighed=weighed,
        weighed_z=z,
        riding=riding,
    )


def reduced_chi2(system: WeightedSystem) -> tuple[float, float, float]:
    """Σ r² / (n − p_eff) over the measured rows, n − p_eff, and the scale row's leverage h (nan without one).

    The measured rows are the masslines and, when weighed, the scale's reading: a datum like any
    massline, whose disagreement with them must raise χ². p_eff = tr(J_d (JᵀJ)⁻¹ J_dᵀ) over those rows
    (:meth:`WeightedSystem.paid_parameters`) counts the parameters the data pay for: the properties and as
    much of each channel's transverse reading as the data, not the prior, determine (E Σ r² = n − p_eff for
    a linear model). Counting the two transverse components of every channel in full (or not at all) makes
    χ² too small on a layout with few hits per channel. χ² is nan when nothing is left over to judge the
    fit by (no redundancy).
    """
    measured = system.measured
    n = system.count
    try:
        paid, leverage = system.paid_parameters(), system.scale_leverage()
    except np.linalg.LinAlgError:
        return np.nan, 0.0, np.nan
    left = n - paid
    return (float(np.sum(measured**2) / left) if left > 0.5 else np.nan), max(left, 0.0), leverage


def studentised(residual: float, leverage: float) -> float:
    """r / √(1 − h): a measured row's residual in σ of its own prediction error (nan when h ≈ 1)."""
    return residual / np.sqrt(1 - leverage) if leverage < 1 - 1e-9 else np.nan
