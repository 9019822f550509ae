"""1-σ of every identified property: the budget of its sources (:mod:`.uncertainty_budget`), and what feeds it.

* the information at the estimate (the masslines' σ from their band fits, the priors, the scale's reading),
  split by :mod:`.uncertainty_budget` into noise, transverse sensitivity and the scale;
* a bootstrap over the sensor lines: the sensors are drawn with replacement and the estimate is repeated; its
  spread (robust: the scaled median absolute deviation) carries what differs from sensor to sensor that no
  per-FRF scatter shows, and widens the noise where it is wider than the budget's sensor-to-sensor sources;
* the truncation of the band fits' tails (``truncation_std``): how far the properties move when the masslines are
  shifted by each tail's next term. It is a systematic error (the same in every draw), negligible where the band
  keeps clear of the resonances and dominant where a stiff support or a flexible body leaves no such band. Each
  massline's shift is the band fit's estimate of the next term (B²/A, D²/C: a single mode's law), held to what
  fitting the next term to the data moves it by (``seen_truncation``): on a small cross-axis massline the
  single-mode law gives B²/A a hundred times what the data show, and that one massline made the whole shift.

``combined_std`` (the larger of the information's and the bootstrap's) serves callers that want the statistical
1-σ alone. The bare body's budget (accelerometer housings taken off, :mod:`.sensor_mass`) comes from the same
draws, each with the housings subtracted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.estimator import Estimate, estimate
from massline.identify.sensor_mass import Housings
from massline.identify.massline_fit import BandFit
from massline.core.uncertainty_budget import UncertaintyBudget
from massline.identify.uncertainty_budget import body_budget, budget_shifts
from massline.core.accuracy import covariance_std
from massline.core.calibration import Calibration
from massline.core.errors import MasslineError, solver_errors
from massline.core.masslines import Masslines
from massline.core.properties import VECTOR_SIZE, property_vector, std_of
from massline.core.rigid_body import RigidBody


def aligned(vector: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Principal axes flipped to point like the reference's (an axis has no sign)."""
    v = vector.copy()
    for k in range(3):
        axis, ref = v[16 + 3 * k : 19 + 3 * k], reference[16 + 3 * k : 19 + 3 * k]
        if axis @ ref < 0:
            v[16 + 3 * k : 19 + 3 * k] = -axis
    return v


def bootstrap(data: Masslines, sigma: np.ndarray, result: Estimate, draws: int, seed: int = 0) -> list[RigidBody]:
    """The bodies of ``draws`` re-estimates on sensors drawn with replacement (the scale's reading kept)."""
    rng = np.random.default_rng(seed)
    bodies = []
    for _ in range(draws):
        pick = rng.integers(len(data.sensors), size=len(data.sensors))
        try:
            with np.errstate(invalid="ignore"):  # a draw can pass through no-bodies (a faulty sensor drawn twice)
                again = estimate(
                    Masslines(data.values[pick], data.sensors[pick], data.exciters),
                    sigma[pick],
                    result.model.planar,
                    result.prior,
                    iterations=8,
                    weighed=result.weighed,
                    riding=result.riding,
                )
        except (MasslineError, np.linalg.LinAlgError):
            continue  # a draw whose sensors cannot see every motion
        bodies.append(again.body)
    return bodies


def robust_std(samples: np.ndarray) -> np.ndarray:
    """1.4826 × the median absolute deviation of each column: the standard deviation for a normal spread,
    unmoved by the few draws that pick a faulty sensor twice and leave the body altogether."""
    return 1.4826 * np.median(np.abs(samples - np.median(samples, axis=0)), axis=0)


def truncation_std(data: Masslines, shift: np.ndarray, sigma: np.ndarray, result: Estimate, weighed=None) -> np.ndarray:
    """How far the 25 property entries move when the masslines move by ``shift`` (n_s, n_e).

    A shift so large that the moved masslines fit no body is taken in halves (up to 1/8) and the move scaled
    back up, as its first order; inf when even that fails. ``weighed``: the scale's reading, as in ``result``.
    """
    planar = result.model.planar
    reference = property_vector(result.body, planar)
    for fraction in (1.0, 0.5, 0.25, 0.125):
        moved = Masslines(data.values - fraction * shift, data.sensors, data.exciters)
        try:
            again = estimate(moved, sigma, planar, result.prior, weighed=weighed, riding=result.riding)
        except (MasslineError, np.linalg.LinAlgError, *solver_errors()):
            continue
        return np.abs(aligned(property_vector(again.body, planar), reference) - reference) / fraction
    return np.full(VECTOR_SIZE, np.inf)


SEEN = 2.0  # the data's move of a massline by its next term is known to this many of the richer fit's 1-σ


def seen_truncation(shift: np.ndarray, fit: BandFit, richer: BandFit) -> np.ndarray:
    """Each massline's truncation ``shift`` (n_s, n_e), (m/s²)/N, no larger than the data show it:
    |A − A'| + SEEN σ', with A' and σ' the massline and 1-σ of the ``richer`` fit, which fits each tail's next
    term (:func:`.massline_fit.fit_band`), against ``fit``'s A."""
    seen = np.abs(fit.values - richer.values) + SEEN * richer.std
    return np.sign(shift) * np.minimum(np.abs(shift), seen)


def combined_std(result: Estimate, bodies: list[RigidBody], draws: int) -> dict:
    """1-σ of mass, CoG, J_G, principal moments and axes (identify's std keys) of ``result``'s body: the larger
    of the information's and the spread of the bootstrap ``bodies`` (the information's alone when fewer than
    half the ``draws`` gave a body)."""
    planar = result.model.planar
    informed = covariance_std(result.model, result.covariance)  # not through its inverse: near-singular ones
    if len(bodies) < max(draws // 2, 2):
        return informed
    reference = property_vector(result.body, planar)
    samples = np.array([aligned(property_vector(b, planar), reference) for b in bodies])
    spread = std_of(robust_std(samples))
    combined = {k: np.fmax(informed[k], spread[k]) for k in spread}
    if planar:
        for key in combined:
            combined[key] = np.where(np.isnan(informed[key]), np.nan, combined[key])
    return combined


def bootstrap_std(result: Estimate, bodies: list[RigidBody], draws: int) -> np.ndarray | None:
    """The robust 1-σ (25 entries) of the bootstrap ``bodies`` about ``result``'s; None when fewer than half the
    ``draws`` gave a body."""
    if len(bodies) < max(draws // 2, 2):
        return None
    reference = property_vector(result.body, result.model.planar)
    return robust_std(np.array([aligned(property_vector(b, result.model.planar), reference) for b in bodies]))


@dataclass(frozen=True, eq=False, kw_only=True)
class Spread:
    """identify's 1-σ of the body as tested and of the bare body, their budgets, and the parts its warnings weigh.

    Attributes
    ----------
    tested : dict
        1-σ of every property of the body as tested (identify's std keys, SI): its budget's sources in quadrature
        (:mod:`.uncertainty_budget`).
    bare : dict
        The same of the bare body: the accelerometer housings taken off the estimate and each draw.
    statistical : dict
        ``bare``'s noise, transverse sensitivity and scale's reading alone (no calibration, no truncation).
    truncation : (25,) array
        How far the property entries move when the masslines move by their tails' next term
        (:func:`truncation_std`), SI.
    budget, tested_budget : UncertaintyBudget
        The bare body's and the tested body's budgets, source by source.
    explained : float
        Σ r² of the fit that the chain's calibration errors at their 1-σ explain (the fit cannot absorb them).
    draws : int
        How many independent calibration errors that is (each channel's and the force transducer's).
    """

    tested: dict
    bare: dict
    statistical: dict
    truncation: np.ndarray
    budget: UncertaintyBudget
    tested_budget: UncertaintyBudget
    explained: float = 0.0
    draws: int = 1


def identified_spread(
    data: Masslines,
    sigma: np.ndarray,
    shift: np.ndarray,
    result: Estimate,
    *,
    bare: Estimate,
    housings: Housings,
    draws: int,
    calibration: Calibration = Calibration(),
) -> Spread:
    """The 1-σ of ``result``'s body and of ``bare``'s (``result`` with the ``housings`` taken off), each the budget
    of its sources (:mod:`.uncertainty_budget`): the information and ``draws`` bootstrap re-estimates (none: the
    information's alone), the ``calibration``'s type-B sources, the truncation of the masslines ``data`` by
    ``shift`` (n_s, n_e), (m/s²)/N (NaN: none); ``sigma`` their 1-σ, (m/s²)/N."""
    planar = result.model.planar
    truncation = truncation_std(data, np.nan_to_num(shift), sigma, result, result.weighed)
    bodies = bootstrap(data, sigma, result, draws) if draws else []
    model_masslines = data.values - np.nan_to_num(result.residual)
    system = result.system
    shifts = budget_shifts(system, result.model, model_masslines, sigma, calibration, chi2_measured=system.measured,
                           dof=result.dof)  # fmt: skip
    options = dict(truncation=truncation)
    tested = body_budget(shifts, result.model, calibration, bootstrap=bootstrap_std(result, bodies, draws), **options)
    bare_bodies = housings.removed_from_each(bodies, planar)
    tolerance = calibration.housings * housings.theta_each(planar).T  # (p, k): each housing's θ at its 1-σ
    budget = body_budget(shifts, bare.model, calibration, bootstrap=bootstrap_std(bare, bare_bodies, draws),
                         housings=tolerance, **options)  # fmt: skip
    return Spread(
        tested=tested.std(), bare=budget.std(), statistical=std_of(budget.statistical, planar=planar),
        truncation=truncation, budget=budget, tested_budget=tested, explained=shifts.explained, draws=shifts.draws,
    )  # fmt: skip


def property_std(data: Masslines, sigma: np.ndarray, result: Estimate, draws: int = 100) -> dict:
    """1-σ of every property of ``result``'s body, the larger of the information's and a ``draws`` bootstrap's."""
    return combined_std(result, bootstrap(data, sigma, result, draws) if draws else [], draws)
