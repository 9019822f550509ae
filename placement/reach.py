"""Reach: whether the hammer can swing in to a point and an accelerometer can stand on it with its cable out.

A hit needs the impact hammer's head to come in along the point's outward normal: a free cylinder of the head's
diameter around the line of approach, over the hammer's swing (``hammer_head``, ``hammer_swing``). An accelerometer
needs its housing (a cylinder of its base's diameter, ``sensor_height`` tall) clear of the part, and its cable's exit:
from half the housing's height, sideways in some direction, free for the connector and the cable's bend
(``cable_run`` beyond the housing's side). Holes, bores, pockets, slots and re-entrant corners narrower than these
hold no point. The checks are ray casts against the mesh (:mod:`massline.meshes.clearance`), every point's in one
call. Lengths in metres, mesh frame.

A line on a mounting block (a direction off the normal) is checked at the point where the block is glued, along
the normal: the block stands there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from massline.meshes.clearance import cylinder_free, side_free

HAMMER_HEAD = 16e-3  # m across: a general-purpose modal hammer's head (about 16 mm, its tip 6 mm)
HAMMER_SWING = 50e-3  # m: the run the head needs clear along the line of approach to strike
SENSOR_HEIGHT = 15e-3  # m: a typical uniaxial or small triaxial modal accelerometer's height
CABLE_RUN = 20e-3  # m: clear beyond the housing's side for the connector and the cable's bend


@dataclass(frozen=True)
class ReachSizes:
    """The instruments' sizes the reach is judged for, m: the hammer's head across and its swing, the
    accelerometer's base across and height, the cable's run beyond the housing."""

    hammer_head: float = HAMMER_HEAD
    hammer_swing: float = HAMMER_SWING
    sensor_base: float = 10e-3
    sensor_height: float = SENSOR_HEIGHT
    cable_run: float = CABLE_RUN


@dataclass(frozen=True, eq=False)
class Reach:
    """Per point: ``approach`` (n,) m, the free length of the hammer's cylinder along the normal (the swing when
    clear); ``housing`` (n,) m, that of the accelerometer's housing (its height when clear); ``cable`` (n,) m, the
    longest free run sideways from half its height (from the axis); ``cable_exit`` (n, 3), its direction."""

    sizes: ReachSizes
    approach: np.ndarray
    housing: np.ndarray
    cable: np.ndarray
    cable_exit: np.ndarray

    @property
    def hit(self) -> np.ndarray:
        """(n,) bool: the hammer swings in clear."""
        return self.approach >= self.sizes.hammer_swing

    @property
    def sensor(self) -> np.ndarray:
        """(n,) bool: the housing stands clear and its cable leaves clear."""
        s = self.sizes
        return (self.housing >= s.sensor_height) & (self.cable >= s.sensor_base / 2 + s.cable_run)

    def take(self, index) -> "Reach":
        return Reach(self.sizes, self.approach[index], self.housing[index], self.cable[index], self.cable_exit[index])

    def entry(self, k: int, side: int) -> dict:
        """plan.json's ``reach`` of point k as a hit (``side`` 1) or an accelerometer (0), m."""
        if side == 1:
            return {
                "approach_m": float(self.approach[k]),
                "swing_m": self.sizes.hammer_swing,
                "clear": bool(self.hit[k]),
            }
        return {
            "housing_m": float(self.housing[k]),
            "height_m": self.sizes.sensor_height,
            "cable_m": float(self.cable[k]),
            "cable_exit": self.cable_exit[k].tolist(),
            "clear": bool(self.sensor[k]),
        }


def approach_free(mesh: trimesh.Trimesh, points: np.ndarray, normals: np.ndarray, sizes: ReachSizes) -> np.ndarray:
    """Free length (n,) m of the hammer head's cylinder along the outward ``normals`` (n, 3) at ``points`` (n, 3)."""
    return cylinder_free(mesh, points, normals, sizes.hammer_head / 2, sizes.hammer_swing)


def reach(mesh: trimesh.Trimesh, points: np.ndarray, normals: np.ndarray, sizes: ReachSizes) -> Reach:
    """The reach (:class:`Reach`) of surface points (n, 3) m with outward unit ``normals`` (n, 3)."""
    housing = cylinder_free(mesh, points, normals, sizes.sensor_base / 2, sizes.sensor_height)
    cable, exit_ = side_free(mesh, points, normals, sizes.sensor_height / 2, sizes.sensor_base / 2 + sizes.cable_run)
    return Reach(sizes, approach_free(mesh, points, normals, sizes), housing, cable, exit_)


def reaches(mesh: trimesh.Trimesh, point: np.ndarray, normal: np.ndarray, sizes: ReachSizes, side: int) -> bool:
    """Whether the hammer reaches ``point`` (3,) m along its outward ``normal`` (3,) (``side`` 1), or an
    accelerometer stands there with its cable out (``side`` 0)."""
    if side == 1:
        return bool(approach_free(mesh, point[None], normal[None], sizes)[0] >= sizes.hammer_swing)
    housing = cylinder_free(mesh, point[None], normal[None], sizes.sensor_base / 2, sizes.sensor_height)[0]
    if housing < sizes.sensor_height:
        return False
    run = sizes.sensor_base / 2 + sizes.cable_run
    return bool(side_free(mesh, point[None], normal[None], sizes.sensor_height / 2, run)[0][0] >= run)


APPROACH, HOUSING, CABLE = "hammer's approach blocked", "accelerometer's housing blocked", "no way out for its cable"


def unreachable_counts(reach: Reach) -> dict:
    """How many points each reason takes: the hammer's approach, the housing, the cable (a point can fail several),
    each reason with the sizes it was judged for."""
    s = reach.sizes
    return {
        f"{APPROACH} (a {1e3 * s.hammer_head:.3g} mm head over a {1e3 * s.hammer_swing:.3g} mm swing: holes, bores, "
        "pockets, re-entrant corners)": int((~reach.hit).sum()),
        f"{HOUSING} ({1e3 * s.sensor_base:.3g} mm across, {1e3 * s.sensor_height:.3g} mm tall)": int(
            (reach.housing < s.sensor_height).sum()
        ),
        f"{CABLE} ({1e3 * s.cable_run:.3g} mm)": int(
            ((reach.housing >= s.sensor_height) & (reach.cable < s.sensor_base / 2 + s.cable_run)).sum()
        ),
    }


def reach_sentence(dropped: dict, kept: int) -> str:
    """What the reach took of the candidate points (plan.json's ``candidates.dropped`` and ``points``): "reach: places
    dropped (as hits or as accelerometers) for 177 hammer's approach blocked (…); …; 507 candidate points kept"."""
    reasons = [f"{n} {reason}" for reason, n in dropped.items() if n and reason.startswith((APPROACH, HOUSING, CABLE))]
    if not reasons:
        return f"reach: every candidate place is in reach of the hammer and takes an accelerometer; {kept} points kept"
    said = "; ".join(reasons)
    return f"reach: places dropped (as hits or as accelerometers) for {said}; {kept} candidate points kept"
