"""Rebuild the bundled meshes: ``python -m massline.meshes.generate [DIR]``.

Each body is a union of solid boxes (closed forms exist for all of them), meshed
on the grid of all box faces so the surface is watertight with exact
coordinates, and written as OBJ with 17 significant digits (binary STL and PLY
would round to float32).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation


@dataclass(frozen=True)
class Box:
    """An axis-aligned solid box between corners ``lo`` and ``hi`` (m)."""

    lo: tuple
    hi: tuple


@dataclass(frozen=True)
class BoxBody:
    """Disjoint boxes of one density (kg/m³), then rotated by R and moved by t."""

    boxes: tuple
    density: float
    rotation: tuple = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    translation: tuple = (0.0, 0.0, 0.0)


# The paper's aluminium plate, 0.30 × 0.14 × 0.005 m, in the frame of Table 1:
# CoG at (0, 0.0636, 0); the long side is y (J_x ≈ 4.25e-3, J_y ≈ 9.26e-4 kg·m²).
PLATE = BoxBody((Box((-0.07, 0.0636 - 0.15, -0.0025), (0.07, 0.0636 + 0.15, 0.0025)),), 2700.0)

# A 3-D steel structure of the paper's size (≈ 4 kg, CoG a few cm from O): a base
# plate, an upright at one edge and a block in a corner, so every product of
# inertia is non-zero.
STRUCTURE = BoxBody(
    (
        Box((0.0, 0.0, 0.0), (0.16, 0.12, 0.012)),
        Box((0.0, 0.0, 0.012), (0.012, 0.12, 0.15)),
        Box((0.012, 0.0, 0.012), (0.062, 0.04, 0.052)),
    ),
    7850.0,
)

# An aluminium L-bracket turned so that its principal axes are oblique to the frame.
BRACKET = BoxBody(
    (
        Box((0.0, 0.0, 0.0), (0.12, 0.07, 0.01)),
        Box((0.0, 0.0, 0.01), (0.01, 0.07, 0.06)),
        Box((0.01, 0.0, 0.01), (0.04, 0.01, 0.04)),
    ),
    2700.0,
    tuple(map(tuple, Rotation.from_rotvec([0.35, -0.55, 0.8]).as_matrix())),
    (0.02, -0.01, 0.03),
)

BODIES = {"plate": PLATE, "structure": STRUCTURE, "bracket": BRACKET}


def box_union_mesh(boxes) -> trimesh.Trimesh:
    """Watertight surface of a union of axis-aligned boxes.

    The space is cut on the grid of all box faces; a grid cell is solid when its
    centre lies in a box, and every cell face between solid and empty becomes two
    triangles wound outward.
    """
    lo = np.array([b.lo for b in boxes], dtype=float)
    hi = np.array([b.hi for b in boxes], dtype=float)
    grid = [np.unique(np.concatenate([lo[:, a], hi[:, a]])) for a in range(3)]
    centres = np.meshgrid(*[(g[:-1] + g[1:]) / 2 for g in grid], indexing="ij")
    c = np.stack(centres, axis=-1)
    solid = np.zeros(c.shape[:3], dtype=bool)
    for a, b in zip(lo, hi):
        solid |= np.all((c > a) & (c < b), axis=-1)
    solid = np.pad(solid, 1)
    triangles = []
    for a in range(3):
        b_, c_ = (a + 1) % 3, (a + 2) % 3
        change = np.diff(solid.astype(int), axis=a)  # +1: empty → solid going +a, −1: solid → empty
        for idx in np.argwhere(change != 0):
            cell = idx - 1  # index in the unpadded grid of the cell on the −a side
            plane = grid[a][cell[a] + 1]
            u0, u1 = grid[b_][cell[b_]], grid[b_][cell[b_] + 1]
            v0, v1 = grid[c_][cell[c_]], grid[c_][cell[c_] + 1]
            quad = np.zeros((4, 3))
            quad[:, a] = plane
            quad[:, b_] = [u0, u1, u1, u0]
            quad[:, c_] = [v0, v0, v1, v1]
            if change[tuple(idx)] > 0:  # solid on the +a side: normal −a
                quad = quad[::-1]
            triangles += [quad[[0, 1, 2]], quad[[0, 2, 3]]]
    return trimesh.Trimesh(**trimesh.triangles.to_kwargs(np.array(triangles)))


def body_mesh(body: BoxBody) -> trimesh.Trimesh:
    mesh = box_union_mesh(body.boxes)
    transform = np.eye(4)
    transform[:3, :3], transform[:3, 3] = body.rotation, body.translation
    mesh.apply_transform(transform)
    return mesh


def main(argv=None) -> None:
    out = Path((argv or sys.argv[1:] or [Path(__file__).parent])[0])
    for name, body in BODIES.items():
        text = trimesh.exchange.obj.export_obj(body_mesh(body), digits=17, include_normals=False)
        (out / f"{name}.obj").write_text(text)
        print(f"wrote {out / name}.obj")


if __name__ == "__main__":
    main()
