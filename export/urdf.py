"""URDF: one link whose ``<inertial>`` holds the body.

URDF specification (wiki.ros.org/urdf/XML/link): ``<inertial>`` has ``<origin xyz rpy>``, the pose of the
inertial frame relative to the link frame, whose origin "must be at the center of gravity"; ``<mass value>``
in kilograms; ``<inertia ixx ixy ixz iyy iyz izz>``, "the 3x3 rotational inertia matrix, represented in the
inertia frame" — the matrix's own entries, so ixy = J_xy (tensor sign). Lengths in metres (REP 103).

The body is free: a ``world`` link (the root, no inertial: REP 105's convention for the fixed frame) holds it by a
``floating`` joint at the link frame's origin, which MuJoCo's importer makes a free joint (the body falls under
gravity as a body hung on nothing would) and ROS tools read as six unconstrained degrees of freedom. The robot also
carries MuJoCo's URDF extension ``<mujoco><compiler fusestatic="false"/></mujoco>`` (MuJoCo XML Reference, URDF
extensions; other URDF readers skip an element they do not know), so that a reader who removes the joint to fix the
body does not get it fused into the world, weighing nothing.
"""

from __future__ import annotations

from massline.export.header import header_lines, real, xml_comment
from massline.export.units import Units

KEEP_LINK = '<mujoco><compiler fusestatic="false"/></mujoco>'  # MuJoCo's importer keeps the jointless link
CONVENTION = (
    "<inertia> ixx ixy ixz iyy iyz izz are the rotational inertia matrix's entries, ixy = J_xy "
    "(URDF specification, link/inertial); <origin> at the CoG, rpy 0: axes of the link frame"
)


def robot(body, units: Units) -> str:
    """A robot of one free link, ``body`` (a ``Body``: mass kg, CoG m, inertia about the CoG kg·m², tensor sign,
    frame of the recording, which is the link's frame) in its ``<inertial>``; ``units`` are SI."""
    x, y, z = units.lengths(body.cog)
    J = units.inertias(body.inertia)
    inertia = " ".join(
        f'{name}="{real(J[i, j])}"'
        for name, (i, j) in zip(
            ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
        )
    )
    return (
        '<?xml version="1.0"?>\n'
        + xml_comment(header_lines(body, units, CONVENTION))
        + '<robot name="massline_body">\n'
        + f"  {KEEP_LINK}\n"
        + '  <link name="world"/>\n'
        + '  <joint name="free" type="floating">\n'
        + '    <parent link="world"/>\n'
        + '    <child link="body"/>\n'
        + '    <origin xyz="0 0 0" rpy="0 0 0"/>\n'
        + "  </joint>\n"
        + '  <link name="body">\n'
        + "    <inertial>\n"
        + f'      <origin xyz="{real(x)} {real(y)} {real(z)}" rpy="0 0 0"/>\n'
        + f'      <mass value="{real(units.masses(body.mass))}"/>\n'
        + f"      <inertia {inertia}/>\n"
        + "    </inertial>\n"
        + "  </link>\n"
        + "</robot>\n"
    )
