"""Abaqus input: a reference node at the CoG with a MASS element (``*MASS``) and a ROTARYI element
(``*ROTARY INERTIA``).

Abaqus Keywords Reference, ``*ROTARY INERTIA``: data line I11, I22, I33, I12, I13, I23, about the node,
along the global axes when no ORIENTATION is given; Abaqus Analysis User's Guide, "Rotary inertia" (§30.2.1 in
2016): I12 = −∫ρ x₁x₂ dV — the tensor's own entry, J_xy, as massline reports it; "the node is assumed to be the
center of mass". ``*MASS``: data line, the mass magnitude.
"""

from __future__ import annotations

from massline.export.header import commented, header_lines, real
from massline.export.units import Units

NODE_ID, MASS_ID, INERTIA_ID = 1, 1, 2
CONVENTION = (
    "*ROTARY INERTIA I11, I22, I33, I12, I13, I23 with I12 = -int(x1 x2 dm) = J_xy, the tensor's entries "
    "(Abaqus Keywords Reference, *ROTARY INERTIA; Analysis User's Guide, Rotary inertia)"
)


def keywords(body, units: Units) -> str:
    """The node, elements and their properties of ``body`` (a ``Body``: mass kg, CoG m, inertia about the CoG
    kg·m², tensor sign, frame of the recording) in ``units``."""
    x, y, z = units.lengths(body.cog)
    J = units.inertias(body.inertia)
    rows = [
        "*NODE, NSET=MASSLINE_COG",
        f"{NODE_ID}, {real(x)}, {real(y)}, {real(z)}",
        "*ELEMENT, TYPE=MASS, ELSET=MASSLINE_MASS",
        f"{MASS_ID}, {NODE_ID}",
        "*MASS, ELSET=MASSLINE_MASS",
        f"{real(units.masses(body.mass))},",
        "*ELEMENT, TYPE=ROTARYI, ELSET=MASSLINE_INERTIA",
        f"{INERTIA_ID}, {NODE_ID}",
        "*ROTARY INERTIA, ELSET=MASSLINE_INERTIA",
        ", ".join(real(v) for v in (J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2])),
    ]
    return commented(header_lines(body, units, CONVENTION), "** ") + "".join(f"{row}\n" for row in rows)
