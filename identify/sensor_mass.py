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

from massline.identify.consistency import is_consistent
from massline.identify.estimator import Estimate
from massline.core.errors import MasslineError
from massline.core.housing_masses import HousingMasses
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.core.plate import plate_theta
from massline.core.rigid_body import RigidBody, six_from_tensor, steiner

SHARED_HOUSING = 1e-3  # m: channels whose points lie closer share one housing (no two housings fit within 1 mm)


def weight(mass: float) -> str:
    """A housing's mass as an engineer writes it: '25 g', '1.2 kg'."""
    return f"{1e3 * mass:.4g} g" if mass < 1 else f"{mass:.4g} kg"


def file_labels(recording) -> np.ndarray | None:
    """The point label (the file's node) of each sensor line of ``recording``, None when it carries none."""
    labels = recording.sensor_labels
    return None if labels is None else np.array([node for node, _ in labels], dtype=int)


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
    masses : (k,) array
        Mass of each housing, kg.
    points : (k, 3) array
        Where each housing sits, m, test frame.
    labels : (k,) int array
        Each housing's point label (the file's node; 1, 2, … where the lines carry none).
    """

    masses: np.ndarray = field(default_factory=lambda: np.zeros(0))
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    labels: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))

    @classmethod
    def alike(cls, mass: float, points: np.ndarray) -> "Housings":
        """``mass`` kg at each of ``points`` (k, 3), labelled 1, 2, …"""
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        return cls(np.full(len(points), float(mass)), points, np.arange(1, len(points) + 1))

    @classmethod
    def on(cls, sensors: Lines, masses, labels=None) -> "Housings":
        """The housings of ``sensors`` with ``masses`` (kg for each, or :class:`HousingMasses`), one per point
        label (``labels`` of each line, the file's nodes) or, without labels, per point; none weighing 0 kg."""
        masses = masses if isinstance(masses, HousingMasses) else HousingMasses.parse(masses)
        if labels is None:
            points = housing_points(sensors)
            labels_k = np.arange(1, len(points) + 1)
        else:
            labels = np.asarray(labels, dtype=int)
            masses.check_labels(labels)
            labels_k, first = np.unique(labels, return_index=True)
            order = np.argsort(first)
            labels_k, points = labels_k[order], sensors.points[first[order]]
        each = masses.of(labels_k)
        kept = each > 0
        return cls(each[kept], points[kept], labels_k[kept])

    @property
    def count(self) -> int:
        return len(self.points)

    @property
    def total(self) -> float:
        """Their mass together, kg."""
        return float(self.masses.sum())

    @property
    def alike_mass(self) -> float | None:
        """The one mass of every housing, kg (0 with none); None when they differ."""
        if not self.count:
            return 0.0
        return float(self.masses[0]) if np.all(self.masses == self.masses[0]) else None

    def payload(self) -> float | dict:
        """DESIGN.md's ``sensor_mass``: kg per housing, or {label: kg} where they differ."""
        alike = self.alike_mass
        return alike if alike is not None else {str(k): float(m) for k, m in zip(self.labels, self.masses)}

    def describe(self) -> str:
        """'8 accelerometer housings × 25 g' or '3 accelerometer housings: 25, 25, 8 g (points 1, 2, 5)'."""
        alike = self.alike_mass
        if alike is not None:
            return f"{self.count} accelerometer housing{'s' if self.count != 1 else ''} × {weight(alike)}"
        each = ", ".join(weight(m) for m in self.masses)
        return f"{self.count} accelerometer housings: {each} (points {', '.join(str(x) for x in self.labels)})"

    def theta_each(self, planar: bool = False) -> np.ndarray:
        """θ_k of each housing (k, 10 or the plate's 6), SI."""
        return np.array([point_mass_theta(m, r, planar) for m, r in zip(self.masses, self.points)]).reshape(
            self.count, 6 if planar else 10
        )

    def theta(self, planar: bool = False) -> np.ndarray:
        """Σ_k θ_k of the housings in the model's parameters (10, or the plate's 6), SI."""
        return sum(
            (point_mass_theta(m, r, planar) for m, r in zip(self.masses, self.points)), np.zeros(6 if planar else 10)
        )

    def removed_from(self, body: RigidBody, planar: bool = False) -> RigidBody:
        """The bare body: θ_tested − Σ_k θ_k (for a plate, its unobservable entries kept as ``body``'s)."""
        if not self.count:
            return body
        model = RigidModel(body, planar)
        return model.body(model.theta - self.theta(planar))

    def removed_from_each(self, bodies: list, planar: bool = False) -> list:
        """Each of ``bodies`` (a bootstrap's draws) bare, but for those the housings leave no physical body of (a
        draw that picked a faulty sensor twice can leave the body altogether: dropped, as the draws that fail)."""
        bare = []
        for body in bodies:
            try:
                bare.append(self.removed_from(body, planar))
            except MasslineError:
                continue
        return bare

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
                f"--sensor-mass: {self.describe()} leave no physical body of the {found.body.mass:.4g} kg identified "
                "with them on: give each housing's mass in kg"
            )
        bare = RigidModel(found.model.body(theta), planar)
        ratio = found.model.scale / bare.scale
        return replace(found, body=bare.nominal, model=bare, covariance=found.covariance * np.outer(ratio, ratio))
