"""SDFormat: a model of one link whose ``<inertial>`` holds the body.

SDFormat specification (sdformat.org/spec, link → inertial): ``<pose>x y z roll pitch yaw</pose>``, the
inertial frame relative to the link frame, whose origin is the center of mass; ``<mass>`` in kilograms;
``<inertia>`` with ``<ixx> <ixy> <ixz> <iyy> <iyz> <izz>``, the entries of the 3x3 rotational inertia matrix
(ixy = J_xy, tensor sign). Lengths in metres.
"""

from __future__ import annotations

from massline.export.header import header_lines, real, xml_comment
from massline.export.units import Units

VERSION = "1.7"
ENTRIES = (("ixx", 0, 0), ("ixy", 0, 1), ("ixz", 0, 2), ("iyy", 1, 1), ("iyz", 1, 2), ("izz", 2, 2))
CONVENTION = (
    "<inertia> ixx ixy ixz iyy iyz izz are the rotational inertia matrix's entries, ixy = J_xy "
    "(SDFormat specification, link/inertial); <pose> at the CoG, no rotation: axes of the link frame"
)


def model(body, units: Units) -> str:
    """A model of one link, ``body`` (a ``Body``: mass kg, CoG m, inertia about the CoG kg·m², tensor sign,
    frame of the recording, which is the link's frame) in its ``<inertial>``; ``units`` are SI."""
    x, y, z = units.lengths(body.cog)
    J = units.inertias(body.inertia)
    entries = "".join(f"          <{name}>{real(J[i, j])}</{name}>\n" for name, i, j in ENTRIES)
    return (
        '<?xml version="1.0"?>\n'
        + xml_comment(header_lines(body, units, CONVENTION))
        + f'<sdf version="{VERSION}">\n'
        + '  <model name="massline_body">\n'
        + '    <link name="body">\n'
        + "      <inertial>\n"
        + f"        <pose>{real(x)} {real(y)} {real(z)} 0 0 0</pose>\n"
        + f"        <mass>{real(units.masses(body.mass))}</mass>\n"
        + "        <inertia>\n"
        + entries
        + "        </inertia>\n"
        + "      </inertial>\n"
        + "    </link>\n"
        + "  </model>\n"
        + "</sdf>\n"
    )
