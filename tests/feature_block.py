"""A machined block with the features a hammer or a housing cannot enter, in millimetres: 80 × 60 × 30, a Ø8
through-hole, a Ø8 blind hole 12 deep, a slot 6 wide, 30 long and 10 deep, and a pocket 20 × 14, 8 deep, all
from its top face (z = 30); 0.372 kg of aluminium (2700 kg/m³).

Run ``python tests/feature_block.py`` to write tests/fixtures/meshes/feature_block.stl again (trimesh's
booleans, through manifold3d).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

FIXTURE = Path(__file__).parent / "fixtures" / "meshes" / "feature_block.stl"
BLOCK = (80.0, 60.0, 30.0)  # mm, centred on x and y, from z = 0 to 30
HOLES = {"through": ((-25.0, 15.0), 4.0, BLOCK[2]), "blind": ((-25.0, -15.0), 4.0, 12.0)}  # centre, radius, depth
BOXES = {"slot": ((15.0, 15.0), (30.0, 6.0), 10.0), "pocket": ((15.0, -15.0), (20.0, 14.0), 8.0)}  # centre, size, depth


def block() -> trimesh.Trimesh:
    """The block as a closed mesh, mm."""
    body = trimesh.creation.box(extents=BLOCK)
    body.apply_translation([0, 0, BLOCK[2] / 2])
    cutters = []
    for (x, y), radius, depth in HOLES.values():
        hole = trimesh.creation.cylinder(radius, 2 * depth, sections=32)
        hole.apply_translation([x, y, BLOCK[2]])  # from depth below the top to as far above it
        cutters.append(hole)
    for (x, y), (a, b), depth in BOXES.values():
        cut = trimesh.creation.box(extents=(a, b, 2 * depth))
        cut.apply_translation([x, y, BLOCK[2]])
        cutters.append(cut)
    return trimesh.boolean.difference([body, *cutters])


def in_a_feature(points_m: np.ndarray, margin_mm: float = 0.3) -> np.ndarray:
    """Which points (n, 3) m lie on a wall or the floor of a hole, the slot or the pocket (strictly between the
    block's top and bottom faces)."""
    p = np.asarray(points_m) * 1e3
    between = (p[:, 2] < BLOCK[2] - 1e-3) & (p[:, 2] > 1e-3)
    inside = np.zeros(len(p), bool)
    for (x, y), radius, depth in HOLES.values():
        deep = p[:, 2] > BLOCK[2] - depth - margin_mm
        inside |= deep & (np.hypot(p[:, 0] - x, p[:, 1] - y) < radius + margin_mm)
    for (x, y), (a, b), depth in BOXES.values():
        deep = p[:, 2] > BLOCK[2] - depth - margin_mm
        inside |= deep & (np.abs(p[:, 0] - x) < a / 2 + margin_mm) & (np.abs(p[:, 1] - y) < b / 2 + margin_mm)
    return inside & between


if __name__ == "__main__":
    mesh = block()
    mesh.export(FIXTURE)
    print(f"{FIXTURE}: {len(mesh.faces)} faces, {mesh.volume * 2.7e-6:.4f} kg at 2700 kg/m³, watertight {mesh.is_watertight}")
