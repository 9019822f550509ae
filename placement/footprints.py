"""Footprints: an accelerometer and a hit cannot share the same patch of surface.

An accelerometer glued at a point covers a disk of its base (``sensor_base`` across); a hammer's tip
(``hammer_tip`` across) must land clear of it. A hit and an accelerometer conflict when their points are
closer than

    r_h = sensor_base / 2 + hammer_tip / 2,

unless the hit is on the far side of a thin wall, its face's outward normal against the accelerometer's
(n_s · n_h < ``THIN_WALL``): a driving-point hit from behind. Two accelerometers conflict when their centres
are closer than a base, r_s = sensor_base, whichever face they are on. Hits never conflict with each other
(one point may be hit along several directions).

Points in metres, normals unit outward, all in the mesh frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError

THIN_WALL = -0.5  # n_s · n_h below this: the hit is on the opposite face, behind the accelerometer


@dataclass(frozen=True, eq=False)
class Sites:
    """Points (n, 3) m and their outward normals (n, 3)."""

    points: np.ndarray
    normals: np.ndarray

    def __len__(self) -> int:
        return len(self.points)

    def take(self, index) -> "Sites":
        index = np.asarray(index, dtype=int)
        return Sites(self.points[index].reshape(-1, 3), self.normals[index].reshape(-1, 3))

    def __add__(self, other: "Sites") -> "Sites":
        return Sites(np.vstack([self.points, other.points]), np.vstack([self.normals, other.normals]))

    @classmethod
    def none(cls) -> "Sites":
        return cls(np.zeros((0, 3)), np.zeros((0, 3)))


@dataclass(frozen=True)
class Footprint:
    """The accelerometer's base and the hammer's tip, m across."""

    sensor_base: float
    hammer_tip: float

    @property
    def hit_reach(self) -> float:
        """r_h (m): the least distance from a hit to an accelerometer on the same side."""
        return self.sensor_base / 2 + self.hammer_tip / 2


def close(a: Sites, b: Sites, reach: float, thin_wall: bool) -> np.ndarray:
    """(n_a, n_b) bool: is point i of ``a`` closer than ``reach`` (m) to point j of ``b``, and, with
    ``thin_wall``, not on the opposite face (n_a · n_b ≥ THIN_WALL)?"""
    gap = np.linalg.norm(a.points[:, None, :] - b.points[None, :, :], axis=2)
    near = gap < reach
    return near & (a.normals @ b.normals.T >= THIN_WALL) if thin_wall else near


def blocked(a: Sites, b: Sites, reach: float, thin_wall: bool) -> np.ndarray:
    """(n_a,) bool: which points of ``a`` conflict with any point of ``b`` (:func:`close`)."""
    if not len(a) or not len(b):
        return np.zeros(len(a), dtype=bool)
    return close(a, b, reach, thin_wall).any(axis=1)


def sensors_blocked(candidates: Sites, sensors: Sites, hits: Sites, footprint: Footprint) -> np.ndarray:
    """(n,) bool: the accelerometer candidates that the placed accelerometers (a base) or hits (r_h, the thin-wall
    exception) leave no room for."""
    return blocked(candidates, sensors, footprint.sensor_base, False) | blocked(
        candidates, hits, footprint.hit_reach, True
    )


def hits_blocked(candidates: Sites, sensors: Sites, footprint: Footprint) -> np.ndarray:
    """(n,) bool: the hit candidates that land on a placed accelerometer's footprint (r_h, thin-wall exception)."""
    return blocked(candidates, sensors, footprint.hit_reach, True)


def accelerometers(sites: Sites) -> Sites:
    """One site per accelerometer: lines through the same point (a triaxial's three) are one accelerometer."""
    _, first = np.unique(np.round(sites.points, 12), axis=0, return_index=True)
    return sites.take(np.sort(first))


def conflicts(sensors: Sites, hits: Sites, footprint: Footprint) -> list[tuple[str, int, int, float]]:
    """Every conflicting pair of a layout, as (kind, i, j, distance m): ("sensors", i < j) two accelerometers
    (their lines' indices) closer than a base at distinct points, ("hit", i, j) accelerometer line i and hit j."""
    out = []
    s_near = close(sensors, sensors, footprint.sensor_base, False)
    distinct = np.linalg.norm(sensors.points[:, None] - sensors.points[None], axis=2) > 1e-12
    for i, j in zip(*np.nonzero(np.triu(s_near & distinct, 1))):
        out.append(("sensors", int(i), int(j), float(np.linalg.norm(sensors.points[i] - sensors.points[j]))))
    if len(sensors) and len(hits):
        for i, j in zip(*np.nonzero(close(sensors, hits, footprint.hit_reach, True))):
            out.append(("hit", int(i), int(j), float(np.linalg.norm(sensors.points[i] - hits.points[j]))))
    return out


def check_fixed(sensors: Sites, hits: Sites, footprint: Footprint) -> None:
    """Refuse fixed accelerometers and hits (``--fixed-sensor``, ``--fixed-exciter``, 1-based in the order given)
    that conflict with each other, naming the first pair."""
    found = conflicts(sensors, hits, footprint)
    if not found:
        return
    kind, i, j, gap = found[0]
    if kind == "sensors":
        raise MasslineError(
            f"--fixed-sensor {i + 1} and --fixed-sensor {j + 1} are {1e3 * gap:.3g} mm apart: two accelerometers "
            f"need a base ({1e3 * footprint.sensor_base:.3g} mm) between their centres"
        )
    raise MasslineError(
        f"--fixed-exciter {j + 1} is {1e3 * gap:.3g} mm from --fixed-sensor {i + 1} on the same side: a hit needs "
        f"{1e3 * footprint.hit_reach:.3g} mm (half the base plus half the tip) from an accelerometer"
    )


def spacing(side: int, normal: np.ndarray, sides: np.ndarray, normals: np.ndarray, footprint: Footprint) -> np.ndarray:
    """(k,) m: the least distance a point of ``side`` (0 accelerometer, 1 hit) with outward ``normal`` (3,) keeps
    from k others of ``sides`` with ``normals`` (k, 3): a base between accelerometers, r_h between a hit and an
    accelerometer facing its way (0 behind a thin wall), 0 between hits."""
    facing = normals @ normal >= THIN_WALL
    across = np.where(facing, footprint.hit_reach, 0.0)
    alike = footprint.sensor_base if side == 0 else 0.0
    return np.where(sides == side, alike, across)


@dataclass(frozen=True, eq=False)
class Footprints:
    """What the planner keeps apart: the footprint, the candidate points' sites (the ``node`` of a side's
    candidate lines indexes them), and the sites of the fixed accelerometer lines and hits."""

    footprint: Footprint
    candidates: Sites
    fixed_sensors: Sites
    fixed_hits: Sites
