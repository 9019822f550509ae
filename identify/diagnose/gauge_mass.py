"""A force gauge's mass at every drive point, found in the masslines alone.

Column j of a shaker test's FRF matrix weighs the body plus the gauge's structure side m_g at drive point r_j
(:mod:`massline.identify.exciter_mass`): H_ij = ℓ_iᵀ M(θ + m_g φ(r_j))⁻¹ ℓ_j, with φ(r) a unit point mass's
parameters. The columns then disagree about the body in a pattern no one body makes, so m_g is seen in the
data: χ²(m) is identify's weighted χ² (its estimator, its σ) with every column fitted on its own body, profiled
over m ≥ 0. The gauge is named when

* the drop χ²(0) − χ²(m̂) is beyond chance for one parameter (p < CHANCE), counted in the misfit's own units
  (divided by the reduced χ² left at m̂ when that is above 1),
* m̂ lies SIGMAS of its 1-σ from zero (1-σ from χ²'s curvature, scaled as the drop),
* the gauge explains the misfit: the reduced χ² left at m̂ is at most EXPLAINED of χ²(0)'s, or within
  chance of 1 (a sensor's gain fault, which one mass per drive point cannot make, is left to the search),
* and it is a gauge: lighter than LARGEST of the bare body fitted with it, not only of identify's (two swapped
  channels on the structure made identify's body 6,494 kg, and a "gauge" of 201 kg left a bare body of 0 kg).

The body fitted with it is the bare body; the recording is then shifted column by column onto that body's
masslines (by the fitted model: ΔH_ij = ℓ_iᵀ (M⁻¹ − M_j⁻¹) ℓ_j) for the search of the other effects.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize_scalar

from massline.core.chi_square import chi2_isf
from massline.core.information import sensitivities
from massline.identify.diagnose.effects.excitation_mass_loading import ExcitationMassLoading
from massline.identify.diagnose.finding import Finding
from massline.identify.estimator import Estimate, estimate
from massline.identify.exciter_mass import riding_masses

CHANCE = 1e-3  # tail probability beyond which a drop in χ² is no longer chance
SIGMAS = 5.0  # the gauge's mass must be this many σ from zero
EXPLAINED = 0.1  # and leave at most this share of the reduced χ² without it (or be within chance of 1)
UNFIT = 1e300  # χ² of a gauge no body fits (finite: the bounded search compares it)
LARGEST = 0.2  # the heaviest gauge weighed, as a share of the body's mass per drive point (the bracket's 20 g: 5.8 %)


@dataclass(frozen=True, eq=False)
class GaugeMass:
    """The gauge found: its ``mass`` (kg) and 1-σ ``std``, the weighted χ² (sums) without and with it, and the
    estimate of the bare body with it (``fit``)."""

    mass: float
    std: float
    chi2_before: float
    chi2_after: float
    fit: Estimate

    def finding(self) -> Finding:
        parameters = {"mass_kg": self.mass, "mass_std_kg": self.std, "drive_points": len(self.fit.riding)}
        evidence = {"chi2_before": self.chi2_before, "chi2_after": self.chi2_after, "dof": 1}
        return Finding(ExcitationMassLoading.name, (), None, parameters, evidence)

    def column_shift(self, sensors, exciters) -> np.ndarray:
        """ΔH (n_s, n_e), (m/s²)/N: the bare body's masslines less those of the bodies the exciters drove."""
        model = self.fit.model
        s, e = model.coordinates(sensors), model.coordinates(exciters)
        return sensitivities(model, s, e)[1] - sensitivities(model, s, e, self.fit.riding)[1]


def chi2_sum(found: Estimate) -> float:
    """The weighted residuals' χ² (not reduced)."""
    return float(found.chi2 * found.dof)


def gauge_mass(data, sigma: np.ndarray, planar: bool, transverse: float, without: Estimate) -> GaugeMass | None:
    """The gauge mass the masslines ``data`` (σ ``sigma``) show, or None; ``without``: identify's estimate
    with no gauge (its χ² the reference)."""
    n_e = len(data.exciters)
    if n_e < 2 or not np.isfinite(without.chi2) or without.dof <= 1:
        return None

    def fitted(m: float) -> Estimate:
        riding = riding_masses(data.exciters, m, planar)
        return estimate(data, sigma, planar, transverse, iterations=20, riding=riding)

    def chi2_at(m: float) -> float:
        try:
            return chi2_sum(fitted(m))
        except (ValueError, np.linalg.LinAlgError):
            return UNFIT

    largest = LARGEST * without.body.mass
    best = minimize_scalar(chi2_at, bounds=(0.0, largest), method="bounded", options={"xatol": 1e-5 * largest})
    m, before = float(best.x), chi2_sum(without)
    if not (m > 0 and best.fun < UNFIT):  # no gauge, or no body fits with any gauge tried (a swapped pair)
        return None
    fit = fitted(m)
    if not np.isfinite(fit.chi2):
        return None
    after = chi2_sum(fit)
    spread = max(fit.chi2, 1.0)  # the misfit's own units
    h = max(1e-2 * m, 1e-6 * largest)
    if m > h:
        curvature = (chi2_at(m + h) - 2 * after + chi2_at(m - h)) / h**2
    else:
        curvature = (chi2_at(m + 2 * h) - 2 * chi2_at(m + h) + after) / h**2
    std = np.sqrt(2 * spread / curvature) if curvature > 0 else np.inf
    beyond_chance = (before - after) / spread > chi2_isf(CHANCE, 1)
    explains = fit.chi2 <= max(EXPLAINED * without.chi2, chi2_isf(CHANCE, fit.dof) / fit.dof)
    plausible = m < 0.99 * min(largest, LARGEST * fit.body.mass)  # the bare body too carries it: a gauge, not a body
    if not (beyond_chance and explains and plausible and m >= SIGMAS * std):
        return None
    return GaugeMass(mass=m, std=float(std), chi2_before=before, chi2_after=after, fit=fit)


def gauge_pattern(data, sigma: np.ndarray, planar: bool, transverse: float, without: Estimate) -> np.ndarray:
    """ψ (p,), SI per kg: how identify's θ̂ moves per kg of a gauge at every drive point that it left out,
    (θ̂ − θ̂_δ)/δ with θ̂_δ fitted with δ kg riding at each (δ a thousandth of the body per drive point)."""
    delta = 1e-3 * without.body.mass / len(data.exciters)
    riding = riding_masses(data.exciters, delta, planar)
    fitted = estimate(data, sigma, planar, transverse, iterations=20, riding=riding)
    return (without.model.theta - fitted.model.theta) / delta


def shifted(recording, gauge: GaugeMass):
    """The recording moved column by column onto the masslines of the bare body the gauge fit found."""
    shift = gauge.column_shift(recording.sensors, recording.exciters)
    return replace(recording, frf=recording.frf + shift[:, :, None])
