"""The plan's predicted accuracy: identify's uncertainty budget (:mod:`massline.core.uncertainty_budget`) before the
test, from what the test will hold.

Each massline A_ij is fitted over the band's spectral lines f_k (identify's band fit: Re H = A + B/x + C x + D x²,
x = ω²/ω_mid²). With each line's noise a relative ``line_noise`` ν of |H| (complex, ν/√2 on each part, as the
virtual test draws it and as a coherence γ² = 1/(1 + ν²) says), A's 1-σ is

    σ_ij = ν/√2 · |H_ij| · √[(XᵀX)⁻¹]₀₀,     X = [1, x⁻¹, x, x²] over the band's lines,

so it falls as 1/√(lines) and rises with the tails the fit must take out. With the masslines H_ij of the
nominal body, their sensitivities and each channel's transverse columns (:mod:`massline.core.information`), the
whitened system is identify's at the nominal body, and the same sources follow: noise, transverse prior, each
accelerometer's and the force transducer's calibration. The band's truncation is not predicted (0): the plan's
band keeps every FRF within its tolerance of its massline.
"""

from __future__ import annotations

import numpy as np

from massline.core.accuracy import property_jacobian
from massline.core.calibration import Calibration
from massline.core.information import driven, sensitivities
from massline.core.lines import Lines, perpendicular_bases, transverse_lines
from massline.core.model import RigidModel
from massline.core.uncertainty_budget import (
    UncertaintyBudget,
    calibration_shifts,
    columns_std,
    dense_jacobian,
    entries_std,
    gains,
)

FIT_POWERS = (0, -1, 1, 2)  # identify's band fit of Re H: A, B/x, C x, D x² (massline_fit.REAL)


def massline_variance_factor(frequencies: np.ndarray) -> float:
    """[(XᵀX)⁻¹]₀₀ of the band fit over the lines ``frequencies`` (Hz): a massline's variance per unit line
    variance; inf with no more lines than the fit's coefficients."""
    f = np.asarray(frequencies, dtype=float)
    if len(f) <= len(FIT_POWERS):
        return np.inf
    x = f**2 / (f.min() * f.max())
    X = x[:, None] ** np.array(FIT_POWERS, dtype=float)[None, :]
    return float(np.linalg.inv(X.T @ X)[0, 0])


def massline_sigma(H: np.ndarray, line_noise: float, frequencies: np.ndarray) -> np.ndarray:
    """Each massline's 1-σ (n_s, n_e), (m/s²)/N, fitted over ``frequencies`` with each line's relative noise
    ``line_noise``."""
    return line_noise / np.sqrt(2) * np.abs(H) * np.sqrt(massline_variance_factor(frequencies))


def predicted_budget(
    model: RigidModel,
    sensors: Lines,
    exciters: Lines,
    *,
    line_noise: float,
    frequencies: np.ndarray,
    calibration: Calibration,
) -> UncertaintyBudget:
    """The budget identify will state for this layout's test: ``model``'s nominal body, the band's spectral lines
    ``frequencies`` (Hz) each with relative noise ``line_noise``, and the chain's ``calibration``."""
    s, e = model.coordinates(sensors), model.coordinates(exciters)
    G, H = sensitivities(model, s, e)
    sigma = np.fmax(massline_sigma(H, line_noise, frequencies), 1e-300)
    D, t = None, calibration.transverse
    if not model.planar and t > 0:
        lines = transverse_lines(sensors.points, perpendicular_bases(sensors.directions))
        D = driven(model, e) @ lines / sigma[:, :, None]
    J = dense_jacobian(G / sigma[:, :, None], D, t)
    gain = gains(J, model.p, H.size, 0)
    sensor, force, _ = calibration_shifts(gain, H, sigma, calibration)
    jacobian = property_jacobian(model)
    parts = {
        "noise": entries_std(jacobian, gain.data @ gain.data.T),
        "transverse": entries_std(jacobian, gain.prior @ gain.prior.T),
        "sensor_calibration": columns_std(jacobian, sensor),
        "force_calibration": columns_std(jacobian, force),
        "weighed_mass": np.zeros(jacobian.shape[0]),
        "housings": np.zeros(jacobian.shape[0]),
        "truncation": np.zeros(jacobian.shape[0]),
    }
    return UncertaintyBudget(parts, calibration, model.planar)
