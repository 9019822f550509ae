"""Pre-test check: where the massline band lies, and a suspension that widens it.

Zone B of Appendix A is the band where the accelerance of the suspended,
elastic body stays within a tolerance of the free rigid body's massline
H₀ = S M_O⁻¹ Wᵀ: above the suspension modes (zone A, error ≈ (f_s/f)²) and
below the first elastic mode (zone C, error ≈ (f/f_a)²).
"""

from __future__ import annotations

import numpy as np

from massline.placement.band import Band
from massline.placement.lines import Lines
from massline.placement.masslines import synthesise
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import CORD_LENGTH, STRETCH, UP, Cord, Suspension

TOLERANCE = 0.01  # relative deviation of the FRF matrix from the massline


def deviation(model: SuspendedBody, sensors: Lines, exciters: Lines, frequencies: np.ndarray) -> np.ndarray:
    """‖H(f) − H₀‖_F / ‖H₀‖_F at each frequency: how far the FRFs sit from the massline."""
    H = model.accelerance(frequencies, sensors.points, sensors.directions, exciters.points, exciters.directions)
    ideal = synthesise(model.loaded, sensors, exciters).values  # the accelerometers are weighed too
    return np.linalg.norm(H - ideal[:, :, None], axis=(0, 1)) / np.linalg.norm(ideal)


def frequency_axis(model: SuspendedBody, points: int = 600) -> np.ndarray:
    """A log-spaced axis from a tenth of the top suspension mode to twice the first elastic mode, Hz."""
    low = max(0.1 * model.suspension_frequencies.max(), 0.1)
    high = 2 * model.first_elastic_frequency if model.n_elastic else 1000 * low
    return np.geomspace(low, high, points)


def predict_band(model: SuspendedBody, sensors: Lines, exciters: Lines, tolerance: float = TOLERANCE) -> Band:
    """The widest run of frequencies where every FRF stays within ``tolerance`` of its massline."""
    f = frequency_axis(model)
    good = deviation(model, sensors, exciters, f) <= tolerance
    low, high = np.nan, np.nan
    if good.any():
        edges = np.flatnonzero(np.diff(np.concatenate([[0], good.astype(int), [0]])))
        runs = edges.reshape(-1, 2)
        start, stop = runs[np.argmax(np.log(f[runs[:, 1] - 1]) - np.log(f[runs[:, 0]]))]
        low, high = f[start], f[stop - 1]
        if stop == len(f) and not model.n_elastic:
            high = np.inf  # a rigid model has no zone C
    top, elastic = float(model.suspension_frequencies.max()), model.first_elastic_frequency
    return Band(low, high, top, elastic, "predicted", tolerance)


def recommend_suspension(
    model: SuspendedBody, top_point: np.ndarray, stretch: float = STRETCH, length: float = CORD_LENGTH, up=UP
) -> Suspension:
    """Appendix A's advice made concrete: one soft, long cord attached close above the CoG.

    Parameters
    ----------
    model : SuspendedBody
        The body as planned (its mass sets the cord stiffness).
    top_point : (3,) array
        Attachment point: the body's surface point straight above the CoG, m.
    stretch : float
        Static stretch of the cord under the weight, m: k = m g / stretch, so the bounce
        mode sits at √(g/stretch)/2π (1.0 Hz for 0.25 m).
    length : float
        Hanging length, m: the pendulum modes fall as √(g/L).
    """
    return Suspension(cords=(Cord.soft(top_point, model.loaded.mass, stretch, length),), up=up)
