"""Masslines: the flat low-frequency accelerance of a free rigid body.

For sensor lines S (rows ℓ_i) and exciter lines W (rows ℓ_j), the massline
matrix is H = S M_O⁻¹ Wᵀ, in (m/s²)/N = 1/kg (DESIGN.md; the paper's ẍ/F).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody


@dataclass(frozen=True, eq=False)
class Masslines:
    """Massline matrix ``values`` (n_sensors, n_exciters), 1/kg, with its lines."""

    values: np.ndarray
    sensors: Lines
    exciters: Lines

    def __post_init__(self):
        H = np.atleast_2d(np.asarray(self.values, dtype=float))
        if H.shape != (len(self.sensors), len(self.exciters)):
            raise MasslineError(
                f"massline matrix is {H.shape} but there are {len(self.sensors)} sensors "
                f"and {len(self.exciters)} exciters: one value per sensor-exciter pair is needed"
            )
        if not np.isfinite(H).all():
            bad = np.argwhere(~np.isfinite(H))[0]
            raise MasslineError(
                f"massline of sensor {bad[0]} / exciter {bad[1]} is NaN or infinite: re-estimate or drop that channel"
            )
        object.__setattr__(self, "values", H)

    def transformed(self, rotation: np.ndarray, translation: np.ndarray) -> "Masslines":
        """The same measurement described in a frame where x' = R x + t."""
        return Masslines(
            self.values,
            self.sensors.transformed(rotation, translation),
            self.exciters.transformed(rotation, translation),
        )


def synthesise(body: RigidBody, sensors: Lines, exciters: Lines) -> Masslines:
    """Exact masslines H = S M_O⁻¹ Wᵀ of a free rigid body."""
    H = sensors.coordinates @ np.linalg.solve(body.mass_matrix, exciters.coordinates.T)
    return Masslines(H, sensors, exciters)
