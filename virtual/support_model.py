"""The test's support acting on the body's FE model: what moves each FRF off its massline in the band.

On a stiff cord or a foam pad the band is squeezed between the support's modes and the first elastic mode,
and the support acts on the elastic modes too (:mod:`.suspended`): every FRF departs from its massline by

    δ_ij(ω) = H_ij(ω) − A_ij,    A_ij = n_iᵀ P(r_i) M⁻¹ P(r_j)ᵀ d_j    (the massline, eq. 14 with K = 0)

with H_ij the suspended body's accelerance. With the mesh, the FE model gives the elastic modes and the support
spec its points and stiffness; two scales, fitted to the record by identify (:mod:`massline.identify.support_fit`),
take up what the spec and the material leave uncertain: ``stiffness`` multiplies every spring of the support
(the cords' axial and the foam's stiffness; the cords' pendulum T/L and gravity stay), ``frequency`` every
elastic natural frequency (√ of Young's modulus over the one assumed).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.meshes.loader import BodyMesh
from massline.virtual.elastic import Material
from massline.virtual.planned_test import FEModel, assumed_material, body_material, fe_model
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Suspension, hung_over


@dataclass(frozen=True)
class ScaledModes:
    """Elastic modes with every natural frequency multiplied by ``factor``, the shapes unchanged (mass-normalised
    shapes do not depend on Young's modulus)."""

    modes: object
    factor: float

    @property
    def omega(self) -> np.ndarray:
        return self.modes.omega * self.factor

    def shapes_at(self, points: np.ndarray) -> np.ndarray:
        return self.modes.shapes_at(points)

    def nearest(self, points: np.ndarray) -> np.ndarray:
        return self.modes.nearest(points)


def stiffer(suspension: Suspension, factor: float) -> Suspension:
    """``suspension`` with every cord's axial stiffness and the foam's stiffness multiplied by ``factor``."""
    cords = tuple(replace(c, stiffness=c.stiffness * factor) for c in suspension.cords)
    foam = None if suspension.foam is None else replace(suspension.foam, stiffness=suspension.foam.stiffness * factor)
    return replace(suspension, cords=cords, foam=foam)


@dataclass(frozen=True, eq=False)
class SupportModel:
    """The support and the free body's elastic modes of the mesh's FE model.

    Attributes
    ----------
    modes : ElasticModes
        Free-free elastic modes of the FE model, mass-normalised (frequencies in rad/s as ``omega``).
    suspension : Suspension
        The support as the user described it (points in m, stiffness in N/m, test frame).
    body : RigidBody
        The mesh's body: its resonances on the support say where to look for the record's, and identify begins
        from it where the raw record gives no body.
    """

    modes: object
    suspension: Suspension
    body: RigidBody

    def body_on_it(
        self, body: RigidBody, stiffness: float = 1.0, frequency: float = 1.0, elastic: bool = True
    ) -> SuspendedBody:
        """``body`` (the body as tested) hung level on the support, springs × ``stiffness``, the elastic modes'
        frequencies × ``frequency`` (no elastic modes unless ``elastic``)."""
        support = hung_over(stiffer(self.suspension, stiffness), body.cog)
        return SuspendedBody(body, ScaledModes(self.modes, frequency) if elastic else None, support)

    def resonances(self, body: RigidBody, stiffness: float = 1.0, frequency: float = 1.0) -> tuple[np.ndarray, float]:
        """(the six support modes (6,), the first elastic mode) of ``body`` on it, Hz."""
        f = self.body_on_it(body, stiffness, frequency).natural_frequencies
        return f[:6], float(f[6])

    def departure(
        self,
        body: RigidBody,
        frequencies: np.ndarray,
        sensors: Lines,
        exciters: Lines,
        stiffness: float = 1.0,
        frequency: float = 1.0,
        elastic: bool = True,
    ) -> np.ndarray:
        """δ_ij(f) = H_ij(f) − A_ij, (m/s²)/N, shape (n_s, n_e, n_f): how far each FRF of ``body`` on the support
        lies from its massline at ``frequencies`` (Hz; 0 at a 0 Hz line, which holds no massline); with
        ``elastic`` False, the rigid body's on the support alone."""
        f = np.asarray(frequencies, dtype=float)
        positive = f > 0
        delta = np.zeros((len(sensors.points), len(exciters.points), len(f)), dtype=complex)
        if not positive.any():
            return delta
        lines = (sensors.points, sensors.directions, exciters.points, exciters.directions)
        held = self.body_on_it(body, stiffness, frequency, elastic).accelerance(f[positive], *lines)
        massline = SuspendedBody(body).accelerance(f[positive][:1], *lines)
        delta[:, :, positive] = held - massline
        return delta


@dataclass(frozen=True)
class SupportSetup:
    """What ``--suspension`` with ``--mesh`` gives identify and diagnose, checked before any work: the support
    under the mesh's body and the material of its FE model."""

    body: BodyMesh
    suspension: Suspension
    material: Material
    assumed: str | None = None

    @classmethod
    def parse(cls, spec: str, body: BodyMesh, mesh_name: str | None = None, material: str | None = None):
        """The support ``spec`` (simulate's ``--suspension``) under ``body``, in ``material`` (a name or 'E,NU';
        default the bundled body's, else the metal closest in density); None for 'none' (a free body)."""
        suspension = Suspension.parse(spec, body.mesh, body.nominal)
        chosen = body_material(body, mesh_name, material)
        assumed = assumed_material(body, mesh_name, material)
        return None if suspension.is_free else cls(body, suspension, chosen, assumed)

    def model(self, progress=None) -> tuple[SupportModel, FEModel]:
        """The support model and the FE model whose modes it holds (from the cache, or solved with ``progress``)."""
        fe = fe_model(self.body, self.material, progress=progress, assumed=self.assumed)
        return SupportModel(fe.modes, self.suspension, self.body.nominal), fe
