"""1-σ of every identified property, from the data: information and bootstrap over the lines.

Two estimates, and the larger is reported for each property:

* the inverse information at the estimate, with each massline's σ from its
  band fit and scaled by the reduced χ² of the fit over all masslines;
* a bootstrap over the sensor lines: the sensors are drawn with replacement
  and the estimate is repeated; its spread (robust: the scaled median absolute
  deviation) carries what differs from sensor to sensor (transverse
  sensitivity, mounting) that no per-FRF scatter shows.

``combined_std`` takes the draws' bodies, so the bare body's 1-σ (accelerometer housings taken off,
:mod:`.sensor_mass`) comes from the same draws, each with the housings subtracted.
"""

from __future__ import annotations

import numpy as np

from massline.identify.estimator import Estimate, estimate
from massline.placement.accuracy import predicted_std
from massline.placement.errors import MasslineError
from massline.placement.masslines import Masslines
from massline.placement.properties import property_vector, std_of
from massline.placement.rigid_body import RigidBody


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
                )
        except (MasslineError, np.linalg.LinAlgError):
            continue  # a draw whose sensors cannot see every motion
        bodies.append(again.body)
    return bodies


def robust_std(samples: np.ndarray) -> np.ndarray:
    """1.4826 × the median absolute deviation of each column: the standard deviation for a normal spread,
    unmoved by the few draws that pick a faulty sensor twice and leave the body altogether."""
    return 1.4826 * np.median(np.abs(samples - np.median(samples, axis=0)), axis=0)


def combined_std(result: Estimate, bodies: list[RigidBody], draws: int) -> dict:
    """1-σ of mass, CoG, J_G, principal moments and axes (identify's std keys) of ``result``'s body: the larger
    of the information's and the spread of the bootstrap ``bodies`` (the information's alone when fewer than
    half the ``draws`` gave a body)."""
    planar = result.model.planar
    informed = predicted_std(result.model, np.linalg.inv(result.covariance))
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


def property_std(data: Masslines, sigma: np.ndarray, result: Estimate, draws: int = 100) -> dict:
    """1-σ of every property of ``result``'s body, the larger of the information's and a ``draws`` bootstrap's."""
    return combined_std(result, bootstrap(data, sigma, result, draws) if draws else [], draws)
