"""Bodies the export tests write and read back, and the recordings they are identified from.

The bundled bracket has strongly oblique principal axes (every product of inertia ~⅓ of a moment); ``far`` is
the bracket turned by 25°, −40°, 65° (xyz) and carried 2.8 m from the origin, so that a product of inertia
written with the wrong sign, or a CoG in the wrong frame, moves a number by far more than any tolerance.
"""

from __future__ import annotations

import numpy as np
from conftest import bundled
from scipy.spatial.transform import Rotation

from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody
from massline.export import Body
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise

TURN = Rotation.from_euler("xyz", [25, -40, 65], degrees=True).as_matrix()
CARRY = np.array([1.2, -2.5, 0.9])  # m
RELATIVE_SIGMA = 1e-3  # the 1-σ given to each property of a body built here, relative to its scale


MOVES = {"bracket": (np.eye(3), np.zeros(3)), "far": (TURN, CARRY)}  # x' = R x + t of each body from the bundled


def rigid_bodies() -> dict[str, RigidBody]:
    """The bracket as bundled and turned and carried far from the origin."""
    bracket = bundled("bracket").nominal
    return {name: bracket.transformed(R, t) for name, (R, t) in MOVES.items()}


def measured(body: RigidBody) -> Body:
    """``body`` as measured: a 1-σ of ``RELATIVE_SIGMA`` of its mass, radius of gyration and largest moment."""
    scale_J = RELATIVE_SIGMA * body.principal_moments[2]
    std = {
        "mass": RELATIVE_SIGMA * body.mass,
        "cog": np.full(3, RELATIVE_SIGMA * body.radius_of_gyration),
        "inertia_cog": np.full((3, 3), scale_J),
        "principal_moments": np.full(3, scale_J),
    }
    return Body.of(body, std=std, note="a body built by the tests")


def record(name: str, path) -> None:
    """A noiseless free test of body ``name`` written to ``path`` (UFF, 0–100 Hz): the structure's hand layout
    moved with the body, as a test of the far bracket has its sensors on it (directions off the axes: the file
    gives each node its coordinate system)."""
    R, t = MOVES[name]
    sensors, exciters = (
        Lines(x.points @ R.T + t, x.directions @ R.T, x.triaxial) for x in (structure_sensors(), structure_exciters())
    )
    recording, _ = run(rigid_bodies()[name], sensors, exciters, setup=Acquisition(100.0, 200, Noise(0, 0)))
    write_uff(path, recording, nodes_dataset=2411)  # 2411 and 2420 keep 16 digits: 15 and 18 keep 6


def assert_same_body(mass: float, cog, inertia, body: RigidBody, rtol: float) -> None:
    """Mass, CoG (against |CoG| + radius of gyration) and inertia about the CoG (against its largest principal
    moment) within ``rtol`` of ``body``'s."""
    assert abs(mass - body.mass) <= rtol * body.mass, (mass, body.mass)
    length = np.linalg.norm(body.cog) + body.radius_of_gyration
    np.testing.assert_allclose(cog, body.cog, rtol=0, atol=rtol * length)
    np.testing.assert_allclose(inertia, body.inertia_cog, rtol=0, atol=rtol * body.principal_moments[2])


def comment_text(text: str, marker: str) -> str:
    """The comment lines of an exported file (those starting with ``marker``) as one unwrapped text."""
    return " ".join(line[len(marker) :].strip() for line in text.splitlines() if line.startswith(marker))
