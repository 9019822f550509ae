"""The reported properties: one vector, one list of quantities, one 1-σ of each.

Every table, page and JSON file of massline shows the same quantities, in the same
order and units: mass, CoG, the inertia tensor about the CoG (tensor sign, upper
triangle), the principal moments and the principal axes. ``property_vector`` lays
them out as 25 numbers (mass, c (3), J_G (9, row-major), moments (3), axes (9,
column by column)); ``std_of`` turns the standard deviations of those 25 numbers
into identify's ``std`` keys (DESIGN.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.rigid_body import RigidBody, principal

VECTOR_SIZE = 25


def in_plane_principal(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A plate's in-plane principal moments (two, ascending, then NaN) and axes (z third)."""
    moments, axes = principal(inertia[:2, :2])
    return np.append(moments, np.nan), np.block([[axes, np.zeros((2, 1))], [np.zeros((1, 2)), np.ones((1, 1))]])


def property_vector(body: RigidBody, planar: bool) -> np.ndarray:
    """mass (kg), c (3, m), J_G (9, kg·m²), principal moments (3, kg·m²), axes (9, columns) as one vector."""
    J = body.inertia_cog
    moments, axes = in_plane_principal(J) if planar else (body.principal_moments, body.principal_axes)
    return np.concatenate([[body.mass], body.cog, J.reshape(-1), moments, axes.T.reshape(-1)])


def reported_values(body: RigidBody, planar: bool = False) -> dict:
    """identify's value keys of a body (DESIGN.md); for plate data the unobservable entries are NaN.

    A plate (§2.3) shows neither z_G, nor J_G's z row and column, nor a third principal moment and axis;
    its principal moments and axes are the in-plane ones (as ``std_of`` orders their 1-σ), which need
    J_G's in-plane entries only.
    """
    if not planar:
        return body.as_dict()
    J = np.array(body.inertia_cog, dtype=float)
    J[2, :] = J[:, 2] = np.nan
    moments, axes = in_plane_principal(J)
    axes[:, 2] = np.nan
    cog = np.array([*body.cog[:2], np.nan])
    return {"mass": body.mass, "cog": cog, "inertia_cog": J, "principal_moments": moments, "principal_axes": axes}


def axes_angles_deg(axes_std: np.ndarray) -> np.ndarray:
    """1-σ angle of each principal axis, degrees, from the 1-σ of its three components (3, 3; columns)."""
    return np.degrees(np.sqrt(np.sum(np.asarray(axes_std) ** 2, axis=0)))


def std_of(s: np.ndarray, axes_deg: np.ndarray | None = None, planar: bool = False) -> dict:
    """identify's ``std`` keys from the 1-σ ``s`` of the 25 entries of ``property_vector``.

    ``axes_deg``: each principal axis's 1-σ angle (degrees); by default from its components. For a plate
    the out-of-plane entries are unobservable: NaN.
    """
    s = np.asarray(s, dtype=float)
    std = {
        "mass": s[0],
        "cog": s[1:4].copy(),
        "inertia_cog": s[4:13].reshape(3, 3).copy(),
        "principal_moments": s[13:16].copy(),
        "principal_axes": s[16:25].reshape(3, 3).T.copy(),
    }
    std["principal_axes_deg"] = axes_angles_deg(std["principal_axes"]) if axes_deg is None else np.array(axes_deg)
    if planar:
        std["cog"][2] = np.nan
        std["inertia_cog"][2, :] = std["inertia_cog"][:, 2] = np.nan
        std["principal_moments"][2] = np.nan
        std["principal_axes"][:, 2] = np.nan
        std["principal_axes_deg"][2] = np.nan
    return std


@dataclass(frozen=True)
class Quantity:
    """One reported quantity: its name, the unit it is shown in and the factor from SI to that unit.

    ``key`` is identify's JSON key it belongs to and ``index`` where it sits there (an int, or (i, j) in
    the inertia tensor); the principal axes have no single value (NaN) and their σ is an angle.
    """

    name: str
    unit: str
    scale: float
    key: str
    index: int | tuple

    def value(self, body: RigidBody, planar: bool = False) -> float:
        """The value in SI units (NaN for a principal axis; for plate data, NaN where unobservable)."""
        if self.key == "principal_axes":
            return np.nan
        if planar:
            return float(np.asarray(reported_values(body, True)[self.key])[self.index])
        return float(np.asarray(getattr(body, self.key))[self.index])

    def resolution_scale(self, body: RigidBody) -> float:
        """The quantity's scale on ``body`` (SI): the mass; for a length the larger of |CoG| and the largest
        radius of gyration; for an inertia the largest principal moment. A value 1e−9 of it is rounding."""
        if self.key == "mass":
            return body.mass
        moment = float(np.max(np.abs(body.principal_moments)))
        if self.key == "cog":
            return max(float(np.linalg.norm(body.cog)), float(np.sqrt(moment / body.mass)))
        return moment

    def sigma(self, std: dict) -> float:
        """Its 1-σ from identify's ``std`` keys, SI (degrees for a principal axis)."""
        key = "principal_axes_deg" if self.key == "principal_axes" else self.key
        return float(np.asarray(std[key])[self.index])


def _inertia_entries() -> list[Quantity]:
    names = "xyz"
    return [
        Quantity(f"J_G {names[i]}{names[j]}", "kg·m²", 1.0, "inertia_cog", (i, j))
        for i in range(3)
        for j in range(i, 3)
    ]


JSON_UNITS = {"mass": "kg", "length": "m", "inertia": "kg m^2", "frequency": "Hz"}
"""The units of every number in the JSON massline writes (identify, diagnose, props: the ``units`` block)."""

QUANTITIES: tuple[Quantity, ...] = (
    Quantity("mass", "kg", 1.0, "mass", ()),
    *(Quantity(f"CoG {a}", "mm", 1e3, "cog", k) for k, a in enumerate("xyz")),
    *_inertia_entries(),
    *(Quantity(f"principal moment {k + 1}", "kg·m²", 1.0, "principal_moments", k) for k in range(3)),
    *(Quantity(f"principal axis {k + 1}", "°", 1.0, "principal_axes", k) for k in range(3)),
)
"""Every reported quantity, in the order every table shows them."""

SUMMARY: tuple[Quantity, ...] = tuple(q for q in QUANTITIES if q.key in ("mass", "cog", "principal_moments"))
"""Mass, CoG and principal moments: the figures a result is judged by."""

TENSOR: tuple[Quantity, ...] = tuple(q for q in QUANTITIES if q.key in ("mass", "cog", "inertia_cog"))
"""Mass, CoG and the inertia tensor's entries: the body as a mesh gives it."""
