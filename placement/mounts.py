"""How each planned point is mounted: on a flat face, on a curve with an adhesive film or a cemented pad, or on
a mounting block (a line off the surface normal), as the technician must prepare it.

An accelerometer's kind follows the gap under its flat base on the surface (:meth:`.Surface.base_gap`):
none on a flat face, at most ``FILM_GAP`` filled by the adhesive, at most ``PAD_GAP`` by a cemented pad.
A hit lands on a flat face or on a curve along its normal. A line whose direction is not the surface's normal
there (``--axes``, or the blocks a surface of revolution needs to see its axial rotation) is on a block: a
small cube glued on the surface, read or struck on its side. Lengths in metres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.placement.mountable import FILM_GAP
from massline.placement.plans import Plan

PARALLEL = 1 - 1e-6  # |d · n| above this: the line is along the surface normal


@dataclass(frozen=True)
class Mount:
    """``kind``: "flat", "film" (curved, an adhesive film fills the gap), "pad" (a cemented pad), "curved" (a
    hit on a curve), "block" or "fixed" (given by the user); ``gap``: under the base (m), 0 for hits."""

    kind: str
    gap: float = 0.0

    @property
    def text(self) -> str:
        """As the console and the report show it: "flat", "film 0.05 mm", "pad 0.47 mm", "block"..."""
        return f"{self.kind} {1e3 * self.gap:.2g} mm" if self.kind in ("film", "pad") else self.kind

    def to_dict(self) -> dict:
        return {"kind": self.kind, "gap_m": self.gap}


def motion_text(twist: np.ndarray) -> str:
    """A rigid motion (v, ω) at the origin (6,) in words, the axis to 3 decimals and its point to 0.1 mm (so that
    one motion found twice, on each side, reads the same): "rotation about the axis along (0, 0, 1) through
    (0, 0, 0) mm" (a screw's pitch left out), or "translation along (1, 0, 0)"."""
    v, w = twist[:3], twist[3:]

    def shown(values: np.ndarray, decimals: int) -> str:
        return "(" + ", ".join(f"{np.round(c, decimals) + 0.0:g}" for c in values) + ")"

    if np.linalg.norm(w) < 1e-9 * max(np.linalg.norm(v), 1e-300):
        return "translation along " + shown(v / np.linalg.norm(v), 3)
    axis, through = shown(w / np.linalg.norm(w), 3), shown(1e3 * np.cross(w, v) / (w @ w), 1)
    return f"rotation about the axis along {axis} through {through} mm"


def mounts(plan: Plan, side: int) -> list[Mount]:
    """The mount of each line of the plan's sensors (``side`` 0) or exciters (1), where sliding left it."""
    lines = (plan.sensors, plan.exciters)[side]
    nodes = (plan.sensor_nodes, plan.exciter_nodes)[side]
    points = plan.candidates
    if points is None:  # planned on candidate lines, not on a mesh
        return [Mount("fixed")] * len(nodes)
    normals = points.normals[np.maximum(nodes, 0)]
    gaps = np.zeros(len(nodes)) if points.gap is None else points.gap[np.maximum(nodes, 0)]
    if plan.sliding is not None and plan.sliding.normals[side] is not None:
        slid = ~np.isnan(plan.sliding.gaps[side])
        normals[slid], gaps[slid] = plan.sliding.normals[side][slid], plan.sliding.gaps[side][slid]
    return [
        Mount("fixed") if n < 0 else mount(d, side == 0 and t >= 0, side, normal, gap)
        for n, d, t, normal, gap in zip(nodes, lines.directions, lines.triaxial, normals, gaps)
    ]


def mount(direction: np.ndarray, triaxial: bool, side: int, normal: np.ndarray, gap: float) -> Mount:
    """One line's mount: its direction against the surface's outward ``normal`` there, and the ``gap`` (m) under
    an accelerometer's base."""
    if not triaxial and abs(direction @ normal) < PARALLEL:
        return Mount("block")
    if gap == 0.0:
        return Mount("flat")
    if side == 1:
        return Mount("curved")
    return Mount("film" if gap <= FILM_GAP else "pad", float(gap))
