"""The accelerometers' housings on the tested body, and the bare body left when they are taken off.

The masslines weigh the body as tested, accelerometers on. Each housing is a point mass m_s (kg) at its
point r_k (m, test frame O xyz), whose parameters about O are

    θ_k = m_s (1, r_k, |r_k|² I − r_k r_kᵀ)        (J about O, tensor sign; DESIGN.md's θ).

M_O is linear in θ (the paper's eq. 9, written about O), so θ_tested = θ_bare + Σ_k θ_k exactly and
θ_bare = θ_tested − Σ_k θ_k. The housings' mass is taken as exact: θ_bare has θ_tested's covariance.
The same holds in the plate's parameters (§2.3), whose J_xx, J_yy, J_xy about O take each housing's
height z_k above the plate into account, up to the plate model's own approximation: housings on one face
lift the CoG off the mid-plane, and the z-lines then see J_xx and J_yy less m z_G² = (Σ m_k z_k)²/m
(relative 1e-5 for 40 g on the paper's plate).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from massline.identify.estimator import Estimate, is_consistent
from massline.core.errors import MasslineError, param
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.core.plate import plate_theta
from massline.core.rigid_body import RigidBody, six_from_tensor, steiner

SHARED_HOUSING = 1e-3  # m: channels whose points lie closer share one housing (no two housings fit within 1 mm)


def parse_sensor_mass(text: str) -> float:
    """``--sensor-mass KG``: the mass of one accelerometer housing, kg (finite, ≥ 0)."""
    try:
        mass = float(text)
    except ValueError:
        mass = np.nan
    if not (np.isfinite(mass) and mass >= 0):
        given = param("sensor_mass", f"'{text}'")
        raise MasslineError(f"{given}: give one accelerometer housing's mass in kg, 0 ≤ KG < inf")
    return mass


def housing_points(sensors: Lines, tolerance: float = SHARED_HOUSING) -> np.ndarray:
    """One point per accelerometer housing, (k, 3) m: channels at one point (a triaxial's three) count once."""
    points: list[np.ndarray] = []
    for r in sensors.points:
        if all(np.linalg.norm(r - p) > tolerance for p in points):
            points.append(r)
    return np.array(points).reshape(-1, 3)


def point_mass_theta(mass: float, point: np.ndarray, planar: bool = False) -> np.ndarray:
    """θ of a point mass (kg) at ``point`` (m): m (1, r, |r|² I − r rᵀ) in 3-D; the plate's six of it."""
    if planar:
        return plate_theta(mass, point, np.zeros((3, 3)))
    return np.concatenate([[mass], mass * np.asarray(point), six_from_tensor(steiner(mass, point))])


@dataclass(frozen=True, eq=False)
class Housings:
    """The accelerometer housings on the body as tested.

    Attributes
    ----------
    mass : float
        Mass of each housing, kg (0: none subtracted).
    points : (k, 3) array
        Where each housing sits, m, test frame.
    """

    mass: float = 0.0
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @classmethod
    def on(cls, sensors: Lines, mass: float) -> "Housings":
        """The housings of ``sensors`` (one per point), each weighing ``mass`` kg (finite, ≥ 0)."""
        if not (np.isfinite(mass) and mass >= 0):
            given = param("sensor_mass", f"{mass:g}")
            raise MasslineError(f"{given}: give one accelerometer housing's mass in kg, 0 ≤ KG < inf")
        return cls(mass, housing_points(sensors) if mass > 0 else np.zeros((0, 3)))

    @property
    def count(self) -> int:
        return len(self.points)

    @property
    def total(self) -> float:
        """Their mass together, kg."""
        return self.mass * self.count

    def theta(self, planar: bool = False) -> np.ndarray:
        """Σ_k θ_k of the housings in the model's parameters (10, or the plate's 6), SI."""
        return sum((point_mass_theta(self.mass, r, planar) for r in self.points), np.zeros(6 if planar else 10))

    def removed_from(self, body: RigidBody, planar: bool = False) -> RigidBody:
        """The bare body: θ_tested − Σ_k θ_k (for a plate, its unobservable entries kept as ``body``'s)."""
        if not self.count:
            return body
        model = RigidModel(body, planar)
        return model.body(model.theta - self.theta(planar))

    def removed(self, found: Estimate) -> Estimate:
        """The estimate of the bare body: its body and model, and θ's covariance carried over unchanged.

        The covariance is stored in scaled parameters θ̃ = θ / s; the bare model's scale s' differs, so
        C̃' = C̃ · (s/s')(s/s')ᵀ. Refused when the housings leave no physical body (mass ≤ 0, or a
        pseudo-inertia that is not positive definite).
        """
        if not self.count:
            return found
        planar = found.model.planar
        theta = found.model.theta - self.theta(planar)
        if theta[0] <= 0 or not (planar or is_consistent(theta, 0.0)):
            raise MasslineError(
                f"--sensor-mass: {self.count} housings of {self.mass:g} kg leave no physical body of the "
                f"{found.body.mass:.4g} kg identified with them on: give one housing's mass in kg"
            )
        bare = RigidModel(found.model.body(theta), planar)
        ratio = found.model.scale / bare.scale
        return replace(found, body=bare.nominal, model=bare, covariance=found.covariance * np.outer(ratio, ratio))
