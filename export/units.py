"""The unit systems an export is written in: lengths and masses scaled from massline's SI.

massline computes in metres and kilograms (DESIGN.md, "Conventions"); a solver deck is often in
millimetres with kilograms or tonnes (the consistent mm–t–s–N system of Nastran and Abaqus models).
Time stays in seconds and force in newtons in every system here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError, param


@dataclass(frozen=True)
class Units:
    """A unit system: its name, the length and mass units and how many of each make a metre and a kilogram."""

    name: str
    length: str
    mass: str
    per_metre: float
    per_kilogram: float

    @property
    def inertia(self) -> str:
        """The unit of an inertia entry, e.g. 'kg m^2'."""
        return f"{self.mass} {self.length}^2"

    def masses(self, kilograms: float) -> float:
        """A mass (kg) in this system's mass unit."""
        return kilograms * self.per_kilogram

    def lengths(self, metres: np.ndarray) -> np.ndarray:
        """Lengths or coordinates (m) in this system's length unit."""
        return np.asarray(metres, dtype=float) * self.per_metre

    def inertias(self, kilogram_metres2: np.ndarray) -> np.ndarray:
        """Inertia entries (kg·m²) in this system's mass × length² unit."""
        return np.asarray(kilogram_metres2, dtype=float) * self.per_kilogram * self.per_metre**2


SI = Units("m-kg", "m", "kg", 1.0, 1.0)
UNITS = {u.name: u for u in (SI, Units("mm-kg", "mm", "kg", 1e3, 1.0), Units("mm-t", "mm", "t", 1e3, 1e-3))}
"""Every unit system an export can be written in, by the name ``--export-units`` takes."""


def unit_system(name: str | Units) -> Units:
    """The unit system called ``name`` (one of ``UNITS``), or ``name`` itself when it is one."""
    if isinstance(name, Units):
        return name
    if name not in UNITS:
        raise MasslineError(
            f"{param('units', repr(name), cli=str(name))}: not a unit system; give one of {', '.join(UNITS)}"
        )
    return UNITS[name]
