"""Sensor mass loading: the identified body differs from the mesh's as accelerometer masses would make it.

A point mass m at p adds m φ(p) to the parameters θ = (m, m c, J_O), with

    φ(p) = (1, p, six(|p|² I − p pᵀ))        (a unit mass's first and second moments about O),

or, on a plate, to its six θ_p = (m, m c_x, m c_y, J_xx, J_yy, J_xy) about O (§2.3) the same entries of φ(p).

Given the difference Δθ = θ̂ − θ_mesh of identify's estimate (or the diagnosis's, ``weighed``) and its
covariance C, two kinds of loading
are weighed, each one unknown mass fitted by weighted least squares, m̂ = φᵀC⁻¹Δθ / φᵀC⁻¹φ, with
χ² = ‖Δθ − m̂ φ‖²_C⁻¹ saying how well it explains the difference:

* every housing alike (what every test has: each accelerometer's own mass), φ = Σ_k φ(p_k);
* one housing heavier than it should be (a heavy sensor, a cable clamp), φ = φ(p_k) for each k;
* each housing its own mass m_k ≥ 0 (triaxials and uniaxials of different makes): non-negative weighted least
  squares over every housing, Δθ = Σ_k m_k φ(p_k); when what it leaves is within chance (no fallback to a
  tenth of χ²₀) and the total it loads lies SIGMAS from zero, it is named where the one-mass hypotheses
  explain nothing, or leave more than chance and EVIDENCE more than it;
* the excitation side: a force gauge of one mass at every drive point, riding only while its exciter drives
  (:mod:`massline.identify.exciter_mass`), φ = ψ the change of identify's θ̂ per kg of gauge it left out
  (given by the caller, from identify's estimator: ψ = (θ̂ − θ̂_δ)/δ, θ̂_δ fitted with δ kg at every drive point).

The finding needs the difference to be real (χ²₀ beyond its chance level for 10 parameters, or 6), the best
hypothesis to explain it (χ² within chance or under a tenth of χ²₀: C leaves out the band's small
model biases), to beat every other by EVIDENCE, and a mass positive and SIGMAS from zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from massline.core.chi_square import chi2_isf
from massline.identify.diagnose.effects.excitation_mass_loading import ExcitationMassLoading
from massline.identify.diagnose.effects.sensor_mass_loading import SensorMassLoading
from massline.identify.diagnose.finding import Finding
from massline.identify.estimator import Estimate
from massline.identify.sensor_mass import Housings, housing_points, point_mass_theta
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody

CHANCE = 1e-3  # tail probability beyond which a χ² is no longer chance
SIGMAS = 5.0  # a loading mass must be this many σ from zero
EXPLAINED = 0.1  # the mass must leave at most this share of χ²₀ (C omits the band's small biases)
EVIDENCE = 10.0  # and fit better than any other hypothesis by this much
SHARED = 1e-3  # m: channels this close share a housing


@dataclass(frozen=True, eq=False)
class MassLoading:
    """The loading found: every housing alike, or one.

    Attributes
    ----------
    housings : Housings
        The loading masses (kg) at their points.
    every : bool
        Every housing alike (True) or one housing (False).
    planar : bool
        Weighed in the plate's six parameters.
    channels : tuple of int
        The loaded accelerometer's channels (one housing), empty for every housing.
    std : float or (k,) array
        1-σ of the mass of each, kg (each its own, when each housing's mass was fitted).
    chi2_before, chi2_after : float
        χ² of the identified body against the mesh's, without and with the masses.
    side : str
        "sensor" (the housings, one mass), "each" (each housing its own mass) or "excitation" (a gauge at every
        drive point; ``housings`` its mass at each).
    """

    housings: Housings
    every: bool
    planar: bool
    channels: tuple
    std: float
    chi2_before: float
    chi2_after: float
    side: str = "sensor"

    def bare(self, body: RigidBody) -> RigidBody:
        """``body`` (identified as tested) with the loading masses taken away."""
        return self.housings.removed_from(body, self.planar)

    def finding(self) -> Finding:
        evidence = {"chi2_before": self.chi2_before, "chi2_after": self.chi2_after, "dof": 6 if self.planar else 10}
        if self.side == "excitation":
            mass, count = self.housings.alike_mass, self.housings.count
            parameters = {"mass_kg": mass, "mass_std_kg": self.std, "drive_points": count, "against_mesh": True}
            return Finding(ExcitationMassLoading.name, (), None, parameters, evidence)
        if self.housings.alike_mass is None or self.side == "each":
            parameters = {
                "masses_kg": self.housings.masses.tolist(),
                "masses_std_kg": np.atleast_1d(self.std).tolist(),
                "housings": self.housings.count,
                "every_housing": False,
                "each_housing": True,
                "points_m": self.housings.points.tolist(),
            }
            return Finding(SensorMassLoading.name, self.channels, None, parameters, evidence)
        parameters = {
            "mass_kg": self.housings.alike_mass,
            "mass_std_kg": self.std,
            "housings": self.housings.count,
            "every_housing": self.every,
            "points_m": self.housings.points.tolist(),
        }
        return Finding(SensorMassLoading.name, self.channels, None, parameters, evidence)


def si_covariance(found: Estimate) -> np.ndarray:
    """θ's covariance in SI (the estimate keeps it in scaled parameters θ̃ = θ / s)."""
    return found.covariance * np.outer(found.model.scale, found.model.scale)


def weighed(found: Estimate, fit) -> tuple[np.ndarray, np.ndarray, bool]:
    """θ̂ (SI), its covariance and ``planar`` to weigh a loading on: identify's, or the diagnosis's final ``fit``
    when its support's tail is the rigid body's (shared by every FRF: on a stiff support's narrow band identify's
    per-FRF tails leave θ loose and the shared support pins it)."""
    if fit is not None and fit.problem.data.shared and fit.body is not None:
        return fit.theta, fit.covariance, fit.problem.layout.planar
    return found.model.theta, si_covariance(found), found.model.planar


def hypotheses(sensors: Lines) -> list[tuple[bool, tuple, np.ndarray]]:
    """(every, channels, housing points) of each loading weighed: every housing, then each one."""
    points = housing_points(sensors, SHARED)
    single = [
        (False, tuple(np.flatnonzero(np.linalg.norm(sensors.points - p, axis=1) <= SHARED)), p[None]) for p in points
    ]
    return ([(True, (), points)] if len(points) > 1 else []) + single


def mass_loading(
    theta: np.ndarray,
    covariance: np.ndarray,
    planar: bool,
    sensors: Lines,
    nominal: RigidBody,
    excitation: tuple[np.ndarray, np.ndarray] | None = None,
) -> MassLoading | None:
    """The loading that best explains θ̂ − θ_mesh (θ̂ SI with its ``covariance``), when the evidence says one does;
    ``excitation``: the drive points (n_e, 3) m and ψ (p,), to weigh a gauge at every drive point too."""
    delta = theta - RigidModel(nominal, planar).theta
    p = len(delta)
    if not (np.isfinite(delta).all() and np.isfinite(covariance).all()):
        return None
    information = np.linalg.pinv(covariance)
    chi2_before = float(delta @ information @ delta)
    if chi2_before < chi2_isf(CHANCE, p):
        return None
    weighed = [(every, channels, points, sum(point_mass_theta(1.0, r, planar) for r in points), "sensor")
               for every, channels, points in hypotheses(sensors)]  # fmt: skip
    if excitation is not None:
        weighed.append((True, (), excitation[0], excitation[1], "excitation"))
    fits = []
    for every, channels, points, phi, side in weighed:
        weight = float(phi @ information @ phi)
        mass = float(phi @ information @ delta) / weight
        rest = delta - mass * phi
        fits.append((float(rest @ information @ rest), every, channels, points, mass, 1 / np.sqrt(weight), side))
    fits.sort(key=lambda f: f[0])
    chi2_after, every, channels, points, mass, std, side = fits[0]
    explains = chi2_after < max(chi2_isf(CHANCE, p - 1), EXPLAINED * chi2_before)
    alone = len(fits) == 1 or fits[1][0] - chi2_after > EVIDENCE
    each = each_housing(delta, information, planar, sensors, nominal, chi2_before)  # also where a gauge fits best
    if not (explains and alone) or mass < SIGMAS * std or mass * len(points) > 0.5 * nominal.mass:
        return each
    within_chance = chi2_after < chi2_isf(CHANCE, p - 1)
    if each is not None and not within_chance and chi2_after - each.chi2_after > EVIDENCE:
        return each  # one mass for the housings leaves more than chance; their own masses do not
    return MassLoading(Housings.alike(mass, points), every, planar, channels, std, chi2_before, chi2_after, side)


def each_housing(
    delta: np.ndarray, information: np.ndarray, planar: bool, sensors: Lines, nominal: RigidBody, chi2_before: float
) -> MassLoading | None:
    """Each housing its own mass m_k ≥ 0 fitted to Δθ (weighted NNLS, the weight's square root from the
    information's eigenpairs), when what it leaves is within chance and their total is SIGMAS from 0 (each
    housing's own mass may be far less certain: housings whose φ nearly align share their mass between them);
    named at the housings SIGMAS from 0, or at every loaded one when none is."""
    points = housing_points(sensors, SHARED)
    phi = np.column_stack([point_mass_theta(1.0, r, planar) for r in points])
    w, V = np.linalg.eigh(information)
    root = (V * np.sqrt(np.clip(w, 0.0, None))).T
    masses = nnls(root @ phi, root @ delta)[0]
    loaded = masses > 0
    rest = delta - phi @ masses
    chi2_after = float(rest @ information @ rest)
    if not loaded.any() or chi2_after > chi2_isf(CHANCE, max(len(delta) - loaded.sum(), 1)):
        return None
    covariance = np.linalg.pinv(phi[:, loaded].T @ information @ phi[:, loaded])
    std, total_std = np.sqrt(np.diag(covariance)), float(np.sqrt(covariance.sum()))
    if masses.sum() < SIGMAS * total_std or masses.sum() > 0.5 * nominal.mass:
        return None
    named = points[loaded][masses[loaded] >= SIGMAS * std]  # the housings it can tell apart; all loaded else
    named = named if len(named) else points[loaded]
    near = np.min(np.linalg.norm(sensors.points[:, None] - named, axis=2), axis=1) <= SHARED
    channels = tuple(int(i) for i in np.flatnonzero(near))
    housings = Housings(masses[loaded], points[loaded], np.flatnonzero(loaded) + 1)
    return MassLoading(housings, False, planar, channels, std, chi2_before, chi2_after, "each")
