"""``Body``: a body's mass, CoG and inertia as measured, with their 1-σ and what was measured — what the
exports write and what a script hands to them.

Conventions (DESIGN.md): the frame of the recording (the file's) O xyz, SI units; ``inertia`` is the inertia
tensor about the CoG with the tensor sign, J = ∫(|r|² I − r rᵀ) dm, so J_xy = −∫xy dm. Entries a test could not
observe (a plate's z_G and the z row and column of J, §2.3) are NaN.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from massline.core.errors import MasslineError, param
from massline.core.files import to_json
from massline.core.properties import JSON_UNITS
from massline.core.rigid_body import RigidBody, principal
from massline.export.formats import write_export
from massline.export.units import SI, Units

PLATE_UNOBSERVED = ("z_G", "J_xz", "J_yz", "J_zz")  # what a plate's test leaves unobserved (§2.3)


@dataclass(frozen=True, eq=False, kw_only=True)
class Body:
    """A body, measured (with its 1-σ) or given (a CAD's values: ``std`` None, and the exports say so).

    Attributes
    ----------
    mass : float
        kg.
    cog : ndarray (3,)
        Centre of gravity, m, in the frame of the recording; NaN where unobserved.
    inertia : ndarray (3, 3)
        Inertia tensor about the CoG, kg·m², tensor sign (J_xy = −∫xy dm), along the frame's axes; NaN where
        unobserved.
    std : dict or None
        The 1-σ as identify's ``std`` keys (``mass``, ``cog``, ``inertia_cog``, …, SI); None for values given, not
        measured (the exports' headers say "given, not measured").
    note : str
        What was measured: the recording, the method and band, the bare body or as tested.
    warnings : tuple of str
        What identify found suspect in the data, one sentence each (a coded warning is kept as its sentence).
    """

    mass: float
    cog: np.ndarray
    inertia: np.ndarray
    std: dict | None = None
    note: str = ""
    warnings: tuple = ()

    def __post_init__(self):
        mass = float(self.mass)
        cog = np.asarray(self.cog, dtype=float).reshape(3)
        J = np.asarray(self.inertia, dtype=float).reshape(3, 3)
        if not (np.isfinite(mass) and mass > 0):
            raise MasslineError(f"{param('mass', f'{mass:g}')}: a body's mass is a finite number > 0 (kg)")
        if np.isinf(cog).any() or np.isinf(J).any():
            raise MasslineError(f"{param('cog')} and {param('inertia')}: give finite numbers (NaN: unobserved)")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "cog", cog)
        object.__setattr__(self, "inertia", 0.5 * (J + J.T))
        object.__setattr__(self, "warnings", tuple(str(w) for w in self.warnings))  # the sentences

    @classmethod
    def of(cls, body: RigidBody, **given) -> Body:
        """The measured body of a kernel ``RigidBody`` (its mass, CoG and J_G); ``given``: the other fields."""
        return cls(mass=body.mass, cog=body.cog, inertia=body.inertia_cog, **given)

    @property
    def unobserved(self) -> tuple[str, ...]:
        """The entries the test could not observe (NaN), by name; empty for a 3-D test."""
        nan = (self.cog[2], self.inertia[0, 2], self.inertia[1, 2], self.inertia[2, 2])
        return tuple(name for name, value in zip(PLATE_UNOBSERVED, nan) if np.isnan(value))

    @property
    def rigid(self) -> RigidBody:
        """The kernel's ``RigidBody`` (refused when entries are unobserved: it holds a whole body)."""
        if self.unobserved:
            raise MasslineError(f"the test left {', '.join(self.unobserved)} unobserved: no whole rigid body")
        return RigidBody(self.mass, self.cog, self.inertia)

    @property
    def principal_moments(self) -> np.ndarray:
        """Principal moments about the CoG, kg·m², ascending (NaN when entries are unobserved)."""
        if self.unobserved:
            return np.full(3, np.nan)
        return principal(self.inertia)[0]

    @property
    def payload(self) -> dict:
        """identify's value keys (DESIGN.md: ``mass``, ``cog``, ``inertia_cog``, principal moments and axes),
        ``std``, ``note``, ``warnings`` and ``units``."""
        if self.unobserved:
            values = {"mass": self.mass, "cog": self.cog, "inertia_cog": self.inertia}
        else:
            values = self.rigid.as_dict()
        return values | {"std": self.std, "note": self.note, "warnings": list(self.warnings), "units": JSON_UNITS}

    def to_json(self) -> str:
        """``payload`` as JSON (NaN as null)."""
        return to_json(self.payload)

    def export(self, path: str | Path, units: str | Units = SI, force: bool = False) -> Path:
        """Write the body to ``path`` in the format its suffix names (``massline.export.FORMATS``), in ``units``
        ('m-kg', 'mm-kg' or 'mm-t'), whole or not at all; an existing file only with ``force``."""
        return write_export(self, path, units, force)
