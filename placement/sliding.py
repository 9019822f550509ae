"""Off the grid: the chosen accelerometers and hits slide on their flat patches to raise the criterion.

After the discrete choice every accelerometer and hit that is not fixed (the lines through one point
move together: a triaxial is one) moves in the plane of its flat patch, r = r₀ + a u + b v, its
directions kept. The lines' coordinates ℓ = (d, r × d) are linear in r, so the information F and the
criterion c(F) (log det F for D-optimality; any smooth function of F plugs in) are smooth in (a, b).

Projected gradient ascent: the gradient by central differences; a point whose step would leave the
mountable region (inside its patch, clearance ≥ what it needs, outside the exclusions) or come onto
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
from massline.placement.footprints import Footprint, Sites, spacing
from massline.core.information import NoiseModel, fisher, log_det
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.placement.mountable import Surface

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
    outward normal (M, 3)."""

    side: np.ndarray
    lines: list
    start: np.ndarray
    face: np.ndarray
    basis: np.ndarray
    need: np.ndarray
    normal: np.ndarray

    @classmethod
    def of(cls, surface: Surface, points: CandidatePoints, nodes: tuple, needs: tuple) -> "Mounts":
        """Every candidate point (node ≥ 0) used by a side; ``nodes`` and ``needs`` per side."""
        rows = [
            (s, np.flatnonzero(n == k), k, need)
            for s, (n, need) in enumerate(zip(nodes, needs))
            for k in np.unique(n[n >= 0])
        ]
        face = np.array([points.faces[k] for *_, k, _ in rows], dtype=int)
        return cls(
            side=np.array([r[0] for r in rows], dtype=int),
            lines=[r[1] for r in rows],
            start=points.points[[r[2] for r in rows]].reshape(-1, 3),
            face=face,
            basis=np.array([plane_basis(n) for n in surface.normal(face)]).reshape(-1, 2, 3),
            need=np.array([r[3] for r in rows], dtype=float),
            normal=surface.normal(face).reshape(-1, 3),
        )


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

    def points(self, x: np.ndarray) -> np.ndarray:
        """Positions (M, 3) m of the movable points at offsets x."""
        return self.mounts.start + np.einsum("mk,mkd->md", x, self.mounts.basis)

    def layout(self, x: np.ndarray) -> tuple[Lines, Lines]:
        """Sensor and exciter lines with the movable points at offsets x."""
        moved = [side.points.copy() for side in self.layout0]
        for s, rows, p in zip(self.mounts.side, self.mounts.lines, self.points(x)):
            moved[s][rows] = p
        return tuple(Lines(p, side.directions, side.triaxial) for p, side in zip(moved, self.layout0))

    def value(self, x: np.ndarray) -> float:
        S, E = self.layout(x)
        return self.criterion(fisher(self.model, self.model.coordinates(S), self.model.coordinates(E), self.noise))

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """∂c/∂x (M, 2) by central differences."""
        h = DIFFERENCE * self.surface.size
        steps = np.eye(x.size).reshape(-1, *x.shape) * h
        return np.array([(self.value(x + e) - self.value(x - e)) / (2 * h) for e in steps]).reshape(x.shape)

    def mountable(self, m: int, point: np.ndarray) -> bool:
        """Is ``point`` (m) on movable point m's patch, clear by its need and not excluded?"""
        face = self.surface.locate(point, int(self.surface.patch[self.mounts.face[m]]))
        if face < 0 or excluded_by(point[None], np.array([face]), self.options)[0][0]:
            return False
        return bool(
            self.surface.clearance(point[None], np.array([face]), self.mounts.need[m])[0] >= self.mounts.need[m]
        )

    def away(self, m: int, point: np.ndarray) -> np.ndarray:
        """In-plane unit vector (2,) pointing from the nearest bound of movable point m away from it (0 if none)."""
        foot = self.surface.nearest(point[None], self.mounts.face[m : m + 1], 2 * self.mounts.need[m])[1][0]
        v = np.nan_to_num(self.mounts.basis[m] @ (point - foot))
        return v / max(np.linalg.norm(v), 1e-300)

    def projected(self, x: np.ndarray, g: np.ndarray) -> np.ndarray:
        """The gradient (M, 2) without its component out of the region at the points that touch a bound."""
        out = g.copy()
        for m, p in enumerate(self.points(x)):
            a = self.away(m, p)
            touching = self.surface.clearance(p[None], self.mounts.face[m : m + 1], 2 * self.mounts.need[m])[0]
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
                point = positions[m] + d @ self.mounts.basis[m]
                return self.apart(m, point, positions) and self.mountable(m, point)

            if not may(d):
                a = self.away(m, positions[m])
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
        for done in range(1, iterations + 1 if len(x) else 1):  # nothing to move: every point fixed or on a curve
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
        moved = np.linalg.norm(x, axis=1)
        return Slide(sensors=sensors, exciters=exciters, before=before, after=value, moved=moved, iterations=done)


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
    patches; a point on a curved region (a facet of a tessellated curve) stays at its candidate, where its normal
    and the gap under its base were measured (sliding along the curve itself is not done).

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
    pinned = [(n >= 0) & surface.curved[points.faces[np.maximum(n, 0)]] for n in nodes]
    mounts = Mounts.of(surface, points, tuple(np.where(p, -1, n) for p, n in zip(pinned, nodes)), options.clearances)
    anchors = (Sites.none(), Sites.none()) if anchors is None else anchors
    held = [Sites(points.points[k], points.normals[k]) for k in (np.unique(n[p]) for p, n in zip(pinned, nodes))]
    slider = Slider(
        surface, model, noise, layout=layout, mounts=mounts, options=options, criterion=criterion,
        admissible=admissible, anchors=(anchors[0] + held[0], anchors[1] + held[1]),
    )  # fmt: skip  (the points on curves are anchors too: the others keep off their footprints)
    return slider.run()
