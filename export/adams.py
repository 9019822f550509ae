"""Adams dataset (.adm): a PART with its CM marker, mass and inertia (IP), and the UNITS it is written in.

Adams/Solver (C++) Statements, PART: ``PART/id, MASS=r, CM=id, IP=xx,yy,zz[,xy,xz,yz]``, the mass-inertia tensor
about the CM marker along its axes, with the note "Adams Solver (C++) defines Ixy, Ixz, and Iyz as positive
integrals … Some references define these terms as the negative of these integrals": Ixy = +∫xy dm = −J_xy.
MARKER: ``QP=x,y,z``, the marker's origin in its part's frame, which is ground's here (no QG, no REULER).
UNITS: ``FORCE=, MASS=, LENGTH=, TIME=``. A dataset's first line is its title; '!' starts a comment; a line
starting with ',' continues the statement above.
"""

from __future__ import annotations

from massline.export.header import commented, header_lines, real
from massline.export.units import Units

GROUND, PART, CM_MARKER = 1, 2, 3
LENGTH = {"m": "METER", "mm": "MILLIMETER"}
MASS = {"kg": "KILOGRAM", "t": "TONNE"}
CONVENTION = (
    "PART IP = Ixx, Iyy, Izz, Ixy, Ixz, Iyz with Ixy = +int(xy dm) = -J_xy, Ixz = -J_xz, Iyz = -J_yz "
    "(Adams/Solver C++ Statements, PART: products of inertia are positive integrals)"
)


def dataset(body, units: Units) -> str:
    """The dataset of ``body`` (a ``Body``: mass kg, CoG m, inertia about the CoG kg·m², tensor sign, frame of
    the recording) in ``units``: ground, the part and its CM marker at the CoG, axes parallel to ground's."""
    x, y, z = units.lengths(body.cog)
    J = units.inertias(body.inertia)
    rows = [
        "massline given body" if body.std is None else "massline measured body",
        *commented(header_lines(body, units, CONVENTION), "! ").splitlines(),
        f"UNITS/FORCE = NEWTON, MASS = {MASS[units.mass]}, LENGTH = {LENGTH[units.length]}, TIME = SECOND",
        f"PART/{GROUND}, GROUND",
        f"PART/{PART}, MASS = {real(units.masses(body.mass))}, CM = {CM_MARKER}",
        f", IP = {real(J[0, 0])}, {real(J[1, 1])}, {real(J[2, 2])}",
        f", {real(-J[0, 1])}, {real(-J[0, 2])}, {real(-J[1, 2])}",
        f"MARKER/{CM_MARKER}, PART = {PART}, QP = {real(x)}, {real(y)}, {real(z)}",
        "END",
    ]
    return "".join(f"{row}\n" for row in rows)
