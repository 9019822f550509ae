"""MuJoCo MJCF: a free body whose ``<inertial>`` holds the body.

MuJoCo XML Reference, body/inertial: ``pos``, the inertial frame's position in the body frame (the CoG);
``mass``; ``fullinertia`` "M(1,1), M(2,2), M(3,3), M(1,2), M(1,3), M(2,3)" of the full inertia matrix M — its
own entries, M(1,2) = J_xy (tensor sign); MuJoCo diagonalises it into ``body_inertia`` and ``body_iquat``.
MuJoCo is unit-free but its defaults (gravity 9.81) are SI: metres and kilograms.
"""

from __future__ import annotations

from massline.export.header import header_lines, real, xml_comment
from massline.export.units import Units

CONVENTION = (
    "fullinertia = M(1,1) M(2,2) M(3,3) M(1,2) M(1,3) M(2,3), the inertia matrix's entries, M(1,2) = J_xy "
    "(MuJoCo XML Reference, body/inertial); pos: the CoG in the body frame, which is the file's"
)


def model(body, units: Units) -> str:
    """A model with one free body, ``body`` (a ``Body``: mass kg, CoG m, inertia about the CoG kg·m², tensor
    sign, frame of the recording, which is the body's frame) in its ``<inertial>``; ``units`` are SI."""
    x, y, z = units.lengths(body.cog)
    J = units.inertias(body.inertia)
    full = " ".join(real(J[i, j]) for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))
    return (
        '<mujoco model="massline_body">\n'
        + xml_comment(header_lines(body, units, CONVENTION), "  ")
        + "  <worldbody>\n"
        + '    <body name="body">\n'
        + '      <freejoint name="body_free"/>\n'
        + f'      <inertial pos="{real(x)} {real(y)} {real(z)}" mass="{real(units.masses(body.mass))}" '
        + f'fullinertia="{full}"/>\n'
        + "    </body>\n"
        + "  </worldbody>\n"
        + "</mujoco>\n"
    )
