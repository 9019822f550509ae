"""identify's uncertainty budget (:mod:`massline.core.uncertainty_budget`) at its estimate: the gains of its weighted
system, the noise as the fit shows it, the bootstrap and the truncation.

The noise's variance is the masslines' rows' K_d K_dᵀ, scaled up by the fit's χ² beyond what the noise and the
type-B sources explain (:func:`noise_scale`); the bootstrap over the sensors, when wider than noise, transverse
and sensor calibration together, widens it too (a sensor the model does not explain). Each δθ̃ is carried to the
body reported, the bare body's where housings are taken off (θ differs by the known housings: the δθ are the same).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.accuracy import property_jacobian
from massline.core.calibration import Calibration
from massline.core.model import RigidModel
from massline.core.uncertainty_budget import (
    Gains,
    UncertaintyBudget,
    calibration_shifts,
    columns_std,
    entries_std,
    gains,
)
from massline.core.chi_square import chi2_isf
from massline.identify.suspicions import CHANCE
from massline.identify.weighted_system import WeightedSystem


BOOTSTRAP_WIDER = 2.0  # a bootstrap spread counts beyond this many times the budget's sensor-to-sensor sources


def explained_chi2(gain: Gains, type_b_rows: np.ndarray) -> float:
    """Σ r² the type-B changes ``type_b_rows`` (n_d, k), each at its 1-σ, leave in the measured rows: E Σ r² of
    independent errors, the part of the fit's χ² the chain's calibration explains (what the fit cannot absorb)."""
    rows = np.zeros((gain.residual_maker.shape[0], type_b_rows.shape[1]))
    rows[: len(type_b_rows)] = type_b_rows
    return float(np.sum((gain.residual_maker @ rows) ** 2))


def noise_scale(measured: np.ndarray, dof: float, explained: float, draws: int) -> float:
    """The factor on the noise's variance: the measured rows' Σ r² less what the calibration can explain by chance,
    over the degrees of freedom ``dof``, at least 1 (1 with no redundancy). The calibration's Σ r² is ``explained``
    on average, but it is a χ² of only ``draws`` errors (each channel's and the force's): what it can explain is its
    CHANCE tail, the bar identify's misfit warning uses (:func:`.suspicions.fit_warnings`), so that a test whose
    calibration errors drew large is not taken for a noisy one."""
    if dof <= 0.5:
        return 1.0
    return max(1.0, (float(np.sum(measured**2)) - explained * chi2_isf(CHANCE, draws) / draws) / dof)


@dataclass(frozen=True, eq=False)
class Shifts:
    """What every body's budget shares: θ̃'s covariance of each row group (in the tested model's scaling), the type-B
    shifts (p, k), and Σ r² the calibration explains in the fit (``explained``, over ``draws`` independent
    errors: each channel's and the force's)."""

    noise: np.ndarray
    transverse: np.ndarray
    weighed: np.ndarray
    sensor: np.ndarray
    force: np.ndarray
    scale: np.ndarray  # the tested model's (m₀, m₀L, m₀L²) per parameter
    explained: float = 0.0
    factor: float = 1.0  # the noise's variance factor (:func:`noise_scale`)
    draws: int = 1


def budget_shifts(system: WeightedSystem, model: RigidModel, masslines: np.ndarray, sigma: np.ndarray,
                  calibration: Calibration, *, chi2_measured: np.ndarray, dof: float) -> Shifts:  # fmt: skip
    """The :class:`Shifts` at an estimate: its weighted ``system`` and ``model``, its model ``masslines`` (n_s, n_e)
    and their 1-σ ``sigma``, (m/s²)/N; ``chi2_measured`` the measured rows' residuals and ``dof`` their degrees of
    freedom (the estimator's)."""
    n_s, n_e, p = system.A.shape
    gain = gains(system.dense()[0], p, n_s * n_e, int(system.scale_row is not None))
    sensor, force, rows = calibration_shifts(gain, masslines, sigma, calibration)
    explained = explained_chi2(gain, rows)
    factor = noise_scale(chi2_measured, dof, explained, rows.shape[1])
    return Shifts(factor * gain.data @ gain.data.T, gain.prior @ gain.prior.T, gain.scale @ gain.scale.T, sensor,
                  force, model.scale, explained, factor, rows.shape[1])  # fmt: skip


def body_budget(shifts: Shifts, model: RigidModel, calibration: Calibration, *, truncation: np.ndarray,
                bootstrap: np.ndarray | None = None, housings: np.ndarray | None = None) -> UncertaintyBudget:  # fmt: skip
    """The budget of the body of ``model`` (the tested body's or the bare one's: θ differs by known housings, so
    every δθ is the same), with the ``truncation`` shift (25 entries, SI) and the ``bootstrap``'s 1-σ (25, or
    None) widening the noise where it is BOOTSTRAP_WIDER times the noise, transverse and accelerometer calibration
    together: a bootstrap over n sensors knows its spread to about √(2/(n − 1)) (±50 % on 9 sensors), and the
    calibration it also draws is already in the budget. ``housings`` (p, k), SI: each housing's θ_k at its mass's
    1-σ, what the bare body moves by (None: the body as tested, which the housings do not move)."""
    housings = np.zeros((model.p, 0)) if housings is None else housings
    ratio = shifts.scale / model.scale  # δθ̃ in this model's scaling
    jacobian = property_jacobian(model) * ratio[None, :]
    parts = {
        "noise": entries_std(jacobian, shifts.noise),
        "transverse": entries_std(jacobian, shifts.transverse),
        "sensor_calibration": columns_std(jacobian, shifts.sensor),
        "force_calibration": columns_std(jacobian, shifts.force),
        "weighed_mass": entries_std(jacobian, shifts.weighed),
        "housings": columns_std(property_jacobian(model) / model.scale[None, :], housings),
        "truncation": np.abs(np.nan_to_num(truncation, nan=0.0)),
    }
    if bootstrap is not None:
        seen = parts["noise"] ** 2 + parts["transverse"] ** 2 + parts["sensor_calibration"] ** 2
        wider = np.nan_to_num(bootstrap, nan=0.0) > BOOTSTRAP_WIDER * np.sqrt(seen)
        widened = np.sqrt(np.clip(bootstrap**2 - seen + parts["noise"] ** 2, 0, None))
        parts["noise"] = np.where(wider, widened, parts["noise"])
    return UncertaintyBudget(parts, calibration, model.planar, shifts.factor)


