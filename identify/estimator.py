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
from functools import partial

import numpy as np

from massline.identify.weighing import WeighedMass
from massline.core.band import GIVE_BAND
from massline.core.errors import MasslineError
from massline.core.lines import perpendicular_bases
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.identify.consistency import constrained_step, is_consistent
from massline.identify.missing_pairs import completed
from massline.identify.weighted_system import Iterate, WeightedProblem, WeightedSystem
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
    axes = None if planar or transverse <= 0 else perpendicular_bases(data.sensors.directions)
    problem = WeightedProblem(
        data=data, sigma=sigma, planar=planar, sensors=model.coordinates(data.sensors),
        exciters=model.coordinates(data.exciters), axes=axes, transverse=transverse, weighed=weighed, riding=riding,
    )  # fmt: skip
    last, constrained = gauss_newton(problem, model, iterations)
    return estimate_at(problem, last, constrained)


def gauss_newton(problem: WeightedProblem, model: RigidModel, iterations: int) -> tuple[Iterate, bool]:
    """Damped Gauss–Newton on ``problem``'s weighted residuals from ``model``'s body, the channels read along
    their axes, for at most ``iterations`` steps: the last iterate, and whether the physical-consistency
    constraint was active (a step taken again inside P(θ) ⪰ ε I, :func:`.consistency.constrained_step`).

    Each step (Δθ̃, Δτ) is :meth:`WeightedSystem.step`'s, damped (:func:`damped`) so that the objective Σr² does
    not rise; it stops where no step lowers it or the step is below 1e-12. MasslineError (``DIVERGED``) where
    the information is singular or a step not finite.
    """
    planar, constrained = problem.planar, False
    # the start as given, not re-centred (θ → body loses J_G's digits far from O)
    model, system, H, tilt = problem.on(model, problem.untilted)
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
        taken = damped(partial(problem.at, model), theta, model.scale * x, tilt, tau, ceiling)
        if taken is None:  # no step along (x, τ) lowers the objective: as far as Gauss–Newton goes
            break
        h, (model, system, H, tilt) = taken
        if h * max(np.abs(x).max(), np.abs(tau).max(initial=0.0)) < 1e-12:
            break
    return Iterate(model, system, H, tilt), constrained


def estimate_at(problem: WeightedProblem, last: Iterate, constrained: bool) -> Estimate:
    """The :class:`Estimate` at the ``last`` iterate of ``problem`` (``constrained``: whether the consistency
    constraint was active): its body; the covariance of θ̃, the inverse information scaled up by the reduced χ²
    (:func:`reduced_chi2`) when that is above 1; the residuals H − model, (m/s²)/N (nan at a missing pair);
    each channel's transverse reading T_i τ_i (n_s, 3); the scale's studentised residual."""
    system, axes = last.system, problem.axes
    chi2, dof, leverage = reduced_chi2(system)
    covariance = np.linalg.inv(system.step()[2]) * (max(chi2, 1.0) if np.isfinite(chi2) else 1.0)
    directions = problem.data.sensors.directions
    readings = np.zeros_like(directions) if axes is None else np.einsum("nak,nk->na", axes, last.tilt)
    z = studentised(system.scale_r, leverage) if problem.weighed is not None else np.nan
    return Estimate(
        body=last.model.nominal,
        model=last.model,
        covariance=covariance,
        chi2=chi2,
        dof=dof,
        residual=np.where(np.isfinite(problem.sigma), problem.data.values - last.masslines, np.nan),
        constrained=constrained,
        transverse=readings,
        prior=0.0 if axes is None else problem.transverse,
        weighed=problem.weighed,
        weighed_z=z,
        riding=problem.riding,
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
