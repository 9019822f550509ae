"""Off the grid: the chosen accelerometers and hits slide on the surface to raise the criterion.

After the discrete choice every accelerometer and hit that is not fixed (the lines through one point
move together: a triaxial is one) moves on its surface. On a flat patch it moves in the patch's plane,
r = r₀ + a u + b v, its directions kept. On a curved region (a tessellated cylinder, a fillet: flat facets
joined across soft creases) it moves along the surface the facets tessellate: r is the region's point nearest
to r₀ + a u + b v (u, v spanning the tangent plane at r₀), and its lines turn with the surface, by the least
rotation that takes the normal at r₀ to the interpolated normal at r (a line along the normal stays along it,
a block's tangential line stays tangential). The lines' coordinates ℓ = (d, r × d) are smooth in r, so the
information F and the criterion c(F) (log det F for D-optimality; any smooth function of F plugs in) are
smooth in (a, b).

Projected gradient ascent: the gradient by central differences; a point whose step would leave the
mountable region (inside its patch or region, clearance ≥ what it needs, outside the exclusions, in reach of the
hammer or with room for the accelerometer and its cable (:mod:`.reach`), and for an
accelerometer on a curve a gap under its base no wider than a pad fills) or come onto
another's footprint (accelerometers a base apart, hits half a base and half a tip from the accelerometers on
their side, fixed ones included: :mod:`.footprints`; the candidate layout starts clear of them) loses the step's
component towards its nearest bound, then halves it until mountable, else stays; a backtracking line
search accepts only layouts that improve the criterion and stay admissible (the caller's test, e.g.
:mod:`.admissible`). Lengths in metres, mesh frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from massline.placement.candidates import CandidateOptions, CandidatePoints, excluded_by
from massline.placement.mountable import PAD_GAP
from massline.placement.footprints import Footprint, Sites, spacing
from massline.core.information import NoiseModel, fisher, log_det
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.placement.mountable import Surface
from massline.placement.reach import reaches

Criterion = Callable[[np.ndarray], float]  # information matrix F (p × p) → value to maximise
Admissible = Callable[[Lines, Lines], bool]  # may the layout (sensors, exciters) be used?
ITERATIONS = 60
FIRST_STEP = 0.02  # of the body's size: the first step of the line search
SMALLEST_STEP = 1e-5  # of the body's size: below this the search stops
DIFFERENCE = 1e-6  # of the body's size: the central-difference step
TRIES = 4  # halvings of a point's step before it stays
TOUCH = 0.01  # a point nearer its bound than (1 + this) × its clearance need touches it
STALL = 1e-6  # an iteration raising the criterion by less than this ends the search


@dataclass(frozen=True, eq=False, kw_only=True)
class Slide:
    """The slid layout, the criterion before and after, how far each moved point went (m), the iterations."""

    sensors: Lines
    exciters: Lines
    before: float
    after: float
    moved: np.ndarray
    iterations: int
    normals: tuple = (None, None)  # per side, the surface's outward normal (n, 3) under each line (NaN: fixed)
    gaps: tuple = (None, None)  # per side, the gap (n,) m under an accelerometer's base there (NaN: fixed)

    @property
    def gain(self) -> float:
        """Increase of the criterion over the candidate layout."""
        return self.after - self.before


def plane_basis(normal: np.ndarray) -> np.ndarray:
    """Two orthonormal vectors (2, 3) spanning the plane normal to the unit ``normal``."""
    u = np.cross(normal, np.eye(3)[int(np.argmin(np.abs(normal)))])
    u /= np.linalg.norm(u)
    return np.array([u, np.cross(normal, u)])


@dataclass(frozen=True, eq=False, kw_only=True)
class Mounts:
    """The points that move: side (0 sensors, 1 exciters), their lines, start (m), face, basis, clearance need,
    outward normal (M, 3) at the start, and whether each lies on a curved region (M,)."""

    side: np.ndarray
    lines: list
    start: np.ndarray
    face: np.ndarray
    basis: np.ndarray
    need: np.ndarray
    normal: np.ndarray
    curved: np.ndarray

    @classmethod
    def of(cls, surface: Surface, points: CandidatePoints, nodes: tuple, needs: tuple) -> "Mounts":
        """Every candidate point (node ≥ 0) used by a side; ``nodes`` and ``needs`` per side."""
        rows = [
            (s, np.flatnonzero(n == k), k, need)
            for s, (n, need) in enumerate(zip(nodes, needs))
            for k in np.unique(n[n >= 0])
        ]
        face = np.array([points.faces[k] for *_, k, _ in rows], dtype=int)
        start = points.points[[r[2] for r in rows]].reshape(-1, 3)
        normal = surface.surface_normal(start, face).reshape(-1, 3)
        return cls(
            side=np.array([r[0] for r in rows], dtype=int),
            lines=[r[1] for r in rows],
            start=start,
            face=face,
            basis=np.array([plane_basis(n) for n in normal]).reshape(-1, 2, 3),
            need=np.array([r[3] for r in rows], dtype=float),
            normal=normal,
            curved=surface.curved[face].astype(bool),
        )


def turning(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The least rotation (3, 3) taking the unit vector ``a`` to the unit vector ``b`` (Rodrigues)."""
    axis, cos = np.cross(a, b), float(a @ b)
    if cos <= -1 + 1e-12:
        raise ValueError("a half turn has no least rotation")
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + K + K @ K / (1 + cos)


class Slider:
    """The criterion of a layout as a function of the in-plane offsets x (M, 2) of its movable points."""

    def __init__(
        self,
        surface: Surface,
        model: RigidModel,
        noise: NoiseModel,
        *,
        layout: tuple,
        mounts: Mounts,
        options: CandidateOptions,
        criterion: Criterion,
        admissible: Admissible,
        anchors: tuple = (Sites.none(), Sites.none()),
    ):
        self.surface, self.model, self.noise, self.layout0 = surface, model, noise, layout
        self.mounts, self.options, self.criterion, self.admissible = mounts, options, criterion, admissible
        self.footprint = Footprint(options.sensor_base, options.hammer_tip)
        self.anchors = anchors[0] + anchors[1]
        self.anchor_side = np.repeat([0, 1], [len(anchors[0]), len(anchors[1])])
        self.placed: dict = {}  # (m, offset bytes) → place(m, offset)

    def place(self, m: int, offset: np.ndarray) -> tuple[np.ndarray, int, np.ndarray]:
        """Movable point m at in-plane ``offset`` (2,) m: its position (3,) m, face (−1 off its flat patch) and
        outward normal (3,); on a curve the region's point nearest to the offset point in the start's tangent
        plane."""
        key = (m, offset.tobytes())
        if key not in self.placed:
            q = self.mounts.start[m] + offset @ self.mounts.basis[m]
            if self.mounts.curved[m]:
                q, face = self.surface.onto_region(q, int(self.surface.smooth[0][self.mounts.face[m]]))
                normal = self.surface.surface_normal(q[None], np.array([face]))[0]
            else:
                face = self.surface.locate(q, int(self.surface.patch[self.mounts.face[m]]))
                normal = self.mounts.normal[m]
            self.placed[key] = q, face, normal
        return self.placed[key]

    def points(self, x: np.ndarray) -> np.ndarray:
        """Positions (M, 3) m of the movable points at offsets x."""
        return np.array([self.place(m, x[m])[0] for m in range(len(x))]).reshape(-1, 3)

    def layout(self, x: np.ndarray) -> tuple[Lines, Lines]:
        """Sensor and exciter lines with the movable points at offsets x, turned with the surface on curves."""
        moved = [side.points.copy() for side in self.layout0]
        turned = [side.directions.copy() for side in self.layout0]
        for m, (s, rows) in enumerate(zip(self.mounts.side, self.mounts.lines)):
            point, _, normal = self.place(m, x[m])
            moved[s][rows] = point
            if self.mounts.curved[m]:
                turned[s][rows] = self.layout0[s].directions[rows] @ turning(self.mounts.normal[m], normal).T
        return tuple(Lines(p, d, side.triaxial) for p, d, side in zip(moved, turned, self.layout0))

    def value(self, x: np.ndarray) -> float:
        S, E = self.layout(x)
        return self.criterion(fisher(self.model, self.model.coordinates(S), self.model.coordinates(E), self.noise))

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """∂c/∂x (M, 2) by central differences."""
        h = DIFFERENCE * self.surface.size
        steps = np.eye(x.size).reshape(-1, *x.shape) * h
        return np.array([(self.value(x + e) - self.value(x - e)) / (2 * h) for e in steps]).reshape(x.shape)

    def mountable(self, m: int, offset: np.ndarray) -> bool:
        """Is movable point m at ``offset`` on its patch or region, clear by its need, not excluded, (an
        accelerometer on a curve) with a gap under its base that a pad fills, and in reach (:mod:`.reach`)?"""
        point, face, normal = self.place(m, offset)
        if face < 0 or excluded_by(point[None], np.array([face]), self.options)[0][0]:
            return False
        if self.surface.clearance(point[None], np.array([face]), self.mounts.need[m])[0] < self.mounts.need[m]:
            return False
        if self.mounts.curved[m] and self.mounts.side[m] == 0 and self.gap(point, face) > PAD_GAP:
            return False
        return reaches(self.surface.mesh, point, normal, self.options.reach_sizes, int(self.mounts.side[m]))

    def gap(self, point: np.ndarray, face: int) -> float:
        """The gap (m) under an accelerometer's base at ``point`` on ``face``."""
        return float(self.surface.base_gap(point[None], np.array([face]), self.options.sensor_base)[0])

    def away(self, m: int, offset: np.ndarray) -> np.ndarray:
        """In-plane unit vector (2,) pointing from the nearest bound of movable point m away from it (0 if none)."""
        point, face, _ = self.place(m, offset)
        foot = self.surface.nearest(point[None], np.array([max(face, 0)]), 2 * self.mounts.need[m])[1][0]
        v = np.nan_to_num(self.mounts.basis[m] @ (point - foot))
        return v / max(np.linalg.norm(v), 1e-300)

    def projected(self, x: np.ndarray, g: np.ndarray) -> np.ndarray:
        """The gradient (M, 2) without its component out of the region at the points that touch a bound."""
        out = g.copy()
        for m in range(len(x)):
            point, face, _ = self.place(m, x[m])
            a = self.away(m, x[m])
            touching = self.surface.clearance(point[None], np.array([max(face, 0)]), 2 * self.mounts.need[m])[0]
            if touching < (1 + TOUCH) * self.mounts.need[m]:
                out[m] -= min(g[m] @ a, 0.0) * a
        return out

    def apart(self, m: int, point: np.ndarray, positions: np.ndarray) -> bool:
        """Does movable point m at ``point`` keep off the footprints of the other movable points at ``positions``
        (M, 3) and of the fixed ones (:func:`.footprints.spacing`), or at least the distance it had?"""
        others = np.arange(len(positions)) != m
        where = np.vstack([positions[others], self.anchors.points])
        sides = np.concatenate([self.mounts.side[others], self.anchor_side])
        normals = np.vstack([self.mounts.normal[others], self.anchors.normals])
        need = spacing(int(self.mounts.side[m]), self.mounts.normal[m], sides, normals, self.footprint)
        before = np.linalg.norm(where - positions[m], axis=1)
        after = np.linalg.norm(where - point, axis=1)
        return bool(np.all(after >= np.minimum(need, before)))

    def moved(self, x: np.ndarray, step: np.ndarray) -> np.ndarray:
        """Offsets after ``step``; a point that would leave its mountable region, or come onto another
        accelerometer, loses the step's component towards its nearest bound, then halves it until it may go,
        else stays."""
        new = x.copy()
        for m, d in enumerate(step):
            positions = self.points(new)

            def may(d: np.ndarray) -> bool:
                return self.apart(m, self.place(m, x[m] + d)[0], positions) and self.mountable(m, x[m] + d)

            if not may(d):
                a = self.away(m, x[m])
                d = d - min(d @ a, 0.0) * a
                for _ in range(TRIES):
                    if may(d):
                        break
                    d = d / 2
                else:
                    continue
            new[m] = x[m] + d
        return new

    def run(self, iterations: int = ITERATIONS) -> Slide:
        x = np.zeros((len(self.mounts.side), 2))
        before = value = self.value(x)
        step, smallest = FIRST_STEP * self.surface.size, SMALLEST_STEP * self.surface.size
        done = 0
        for done in range(1, iterations + 1 if len(x) else 1):  # nothing to move: every point fixed
            g = self.projected(x, self.gradient(x))
            direction = g / max(np.linalg.norm(g, axis=1).max(), 1e-300)
            while step > smallest:
                trial = self.moved(x, step * direction)
                trial_value = self.value(trial)
                if trial_value > value and self.admissible(*self.layout(trial)):
                    x, value, gained = trial, trial_value, trial_value - value
                    step = min(2 * step, FIRST_STEP * self.surface.size)
                    break
                step /= 2
            else:
                break
            if gained < STALL:
                break
        sensors, exciters = self.layout(x)
        moved = np.linalg.norm(self.points(x) - self.mounts.start, axis=1)
        normals, gaps = self.sites(x)
        return Slide(sensors=sensors, exciters=exciters, before=before, after=value, moved=moved, iterations=done,
                     normals=normals, gaps=gaps)  # fmt: skip

    def sites(self, x: np.ndarray) -> tuple[tuple, tuple]:
        """Per side, the outward normal (n, 3) and an accelerometer's gap (n,) m under each line at offsets x
        (NaN for the lines that do not move)."""
        normals = tuple(np.full((len(side), 3), np.nan) for side in self.layout0)
        gaps = tuple(np.full(len(side), np.nan) for side in self.layout0)
        for m, (s, rows) in enumerate(zip(self.mounts.side, self.mounts.lines)):
            point, face, normal = self.place(m, x[m])
            normals[s][rows] = normal
            gaps[s][rows] = self.gap(point, face) if self.mounts.curved[m] and s == 0 else 0.0
        return normals, gaps


def slide(
    surface: Surface,
    model: RigidModel,
    noise: NoiseModel,
    *,
    layout: tuple,
    nodes: tuple,
    points: CandidatePoints,
    options: CandidateOptions,
    admissible: Admissible = lambda sensors, exciters: True,
    criterion: Criterion = log_det,
    anchors: tuple | None = None,
) -> Slide:
    """Slide the layout's (sensors, exciters) points that come from candidates (``nodes`` ≥ 0) on their flat
    patches, or along the smooth surface of their curved region, their lines turning with it.

    Parameters
    ----------
    surface : Surface
        The body's flat patches and edges, m.
    model, noise
        What the information F is computed with.
    layout : (Lines, Lines)
        Sensors and exciters, m, mesh frame.
    nodes : (ndarray, ndarray)
        The candidate point of each line, −1 for a fixed one (it stays).
    points : CandidatePoints
        The candidates the nodes index.
    options : CandidateOptions
        Clearances and exclusions the slid points keep.
    admissible : callable
        Whether a layout (sensors, exciters) may be used (e.g. the paper's equations solve it, well enough).
    criterion : callable
        c(F) to maximise, log det F by default.
    anchors : (Sites, Sites), optional
        The fixed accelerometers' and hits' points (m) and outward normals, whose footprints the points keep off.
    """
    mounts = Mounts.of(surface, points, nodes, options.clearances)
    anchors = (Sites.none(), Sites.none()) if anchors is None else anchors
    slider = Slider(
        surface, model, noise, layout=layout, mounts=mounts, options=options, criterion=criterion,
        admissible=admissible, anchors=anchors,
    )  # fmt: skip
    return slider.run()
