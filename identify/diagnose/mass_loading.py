"""Sensor mass loading: the identified body differs from the mesh's as a mass at an accelerometer would make it.

A point mass m at p adds m φ(p) to the parameters θ = (m, m c, J_O), with

    φ(p) = (1, p, six(|p|² I − p pᵀ))        (a unit mass's first and second moments about O).

Given the difference Δθ = θ̂ − θ_mesh and the covariance C of θ̂, the mass at
accelerometer k is the weighted least squares m̂_k = φ_kᵀC⁻¹Δθ / φ_kᵀC⁻¹φ_k, and
χ²_k = ‖Δθ − m̂_k φ_k‖²_C⁻¹ says how well one mass there explains the difference.
The finding needs the difference to be real (χ²₀ beyond its 10-parameter
chance level), one accelerometer's mass to explain it (χ²_k within chance or
under a tenth of χ²₀: the fit's σ leaves out the band's small model biases),
better than a mass at any other accelerometer, positive and several σ from zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2 as chi2_distribution

from massline.identify.diagnose.effect_fit import Fit
from massline.identify.diagnose.finding import Finding
from massline.placement.rigid_body import RigidBody, six_from_tensor, steiner

CHANCE = 1e-3  # tail probability beyond which a χ² is no longer chance
SIGMAS = 5.0  # a loading mass must be this many σ from zero
EXPLAINED = 0.1  # one mass must leave at most this share of χ²₀ (the fit's σ omits the band's small biases)
EVIDENCE = 10.0  # and fit better than a mass at any other accelerometer by this much


def unit_mass(point: np.ndarray) -> np.ndarray:
    """φ(p): θ of a 1 kg point mass at ``point`` (m)."""
    return np.concatenate([[1.0], point, six_from_tensor(steiner(1.0, point))])


@dataclass(frozen=True, eq=False)
class MassLoading:
    """The mass found at one accelerometer.

    Attributes
    ----------
    channels : tuple of int
        The accelerometer's channels.
    point : (3,) array
        Where it sits, m.
    mass, std : float
        The loading mass and its 1-σ, kg.
    chi2_before, chi2_after : float
        χ² of the identified body against the mesh's, without and with the mass.
    bare : RigidBody
        The identified body with the mass taken away.
    """

    channels: tuple
    point: np.ndarray
    mass: float
    std: float
    chi2_before: float
    chi2_after: float
    bare: RigidBody

    def finding(self) -> Finding:
        parameters = {"mass_kg": self.mass, "mass_std_kg": self.std, "point_m": self.point.tolist()}
        evidence = {"chi2_before": self.chi2_before, "chi2_after": self.chi2_after, "dof": 10}
        return Finding("sensor_mass_loading", self.channels, None, parameters, evidence)


def mass_loading(result: Fit, nominal: RigidBody) -> MassLoading | None:
    """The accelerometer whose mass best explains θ̂ − θ_mesh, when the evidence says one does."""
    layout = result.problem.layout
    if layout.planar:
        return None
    delta = result.theta - nominal.theta
    information = np.linalg.pinv(result.covariance)
    chi2_before = float(delta @ information @ delta)
    if chi2_before < chi2_distribution.isf(CHANCE, 10):
        return None
    fits = []
    for channels in layout.groups:
        point = layout.sensors.points[channels[0]]
        phi = unit_mass(point)
        weight = float(phi @ information @ phi)
        mass = float(phi @ information @ delta) / weight
        rest = delta - mass * phi
        fits.append((float(rest @ information @ rest), channels, point, mass, 1 / np.sqrt(weight)))
    fits.sort(key=lambda f: f[0])
    chi2_after, channels, point, mass, std = fits[0]
    explains = chi2_after < max(chi2_distribution.isf(CHANCE, 9), EXPLAINED * chi2_before)
    alone = len(fits) == 1 or fits[1][0] - chi2_after > EVIDENCE
    if not (explains and alone) or mass < SIGMAS * std or mass > 0.5 * nominal.mass:
        return None
    bare = RigidBody.from_theta(result.theta - mass * unit_mass(point))
    return MassLoading(tuple(channels), point, mass, std, chi2_before, chi2_after, bare)
