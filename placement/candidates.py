"""Candidate points and lines on a body's surface, as a technician can use them.

Points: the mesh vertices, the face centres, the midpoints of the edges inside
flat patches (the centre of a rectangle split in two triangles, where a thin
face has the most room) and area-uniform samples, about ``n_samples`` over the surface, thinned so that no two are closer than half the
mean spacing; each with the outward normal of the face it lies on. Only points
where a hit lands square (a smooth region, clear of sharp edges by the tip's radius,
:mod:`.mountable`) and the hammer swings in clear (:mod:`.reach`) are the hit candidates; those that take the
accelerometer's base, with a gap under it that a film or a cemented pad fills, its housing clear of the part and a
way out for its cable, are the sensor candidates. Lines at each point: the surface normal (a hammer hit, a
uniaxial accelerometer glued on the face) and, optionally, the three global axes
(mounting blocks). A triaxial accelerometer is one candidate of three global-axis
lines through a point. Regions can be excluded (boxes, faces).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from massline.core.errors import MasslineError, param
from massline.core.lines import AXES, Lines
from massline.placement.mountable import PAD_GAP, Surface
from massline.placement.reach import CABLE_RUN, HAMMER_HEAD, HAMMER_SWING, SENSOR_HEIGHT, Reach, ReachSizes, reach
from massline.placement.reach import unreachable_counts

MOST_BLOCKED = 1  # unseen motions the planner offers mounting blocks for (a turned part's axis)
BLOCK = 2  # the budget group of lines on mounting blocks (0 uniaxial on the surface, 1 triaxial)
UNSEEN = 1e-2  # a motion no normal reads with an arm above this share of the body's size is as good as unseen
SENSOR_BASE = 10e-3  # m across: the base of a typical uniaxial or triaxial modal accelerometer
HAMMER_TIP = 6e-3  # m across: a modal hammer's tip


@dataclass(frozen=True)
class CandidateOptions:
    """What may be used, in metres in the mesh frame.

    ``exclude_boxes``: ((lo, hi), ...) regions with no candidate;
    ``exclude_faces``: face indices with no candidate;
    ``sensor_base``, ``hammer_tip``: size across (m) of the accelerometer's base and of the hammer's tip;
    a point takes one where the flat disk of half that size around it is clear of edges (:mod:`.mountable`);
    ``edge_keepout``: a larger distance (m) to keep from edges, sensors and hits alike;
    ``hammer_head``, ``hammer_swing``, ``sensor_height``, ``cable_run``: the reach a hit and an accelerometer need
    (m, :mod:`.reach`);
    ``axes``: add the global axes as line directions (mounting blocks).
    """

    n_samples: int = 400
    axes: bool = False
    exclude_boxes: tuple = ()
    exclude_faces: tuple = ()
    sensor_base: float = SENSOR_BASE
    hammer_tip: float = HAMMER_TIP
    edge_keepout: float = 0.0
    seed: int = 0
    hammer_head: float = HAMMER_HEAD
    hammer_swing: float = HAMMER_SWING
    sensor_height: float = SENSOR_HEIGHT
    cable_run: float = CABLE_RUN

    @property
    def reach_sizes(self) -> ReachSizes:
        """The instruments' sizes the reach is judged for (:mod:`.reach`)."""
        return ReachSizes(self.hammer_head, self.hammer_swing, self.sensor_base, self.sensor_height, self.cable_run)

    @property
    def clearances(self) -> tuple[float, float]:
        """The clearance (m) a sensor and a hit need: half the base or tip, at least the keep-out."""
        return max(self.sensor_base / 2, self.edge_keepout), max(self.hammer_tip / 2, self.edge_keepout)


@dataclass(frozen=True, eq=False)
class CandidatePoints:
    """Points (n, 3) m, outward normals (n, 3), the face each lies on (n,), how many points each exclusion
    took, whether an accelerometer fits at each (n,) and whether the hammer reaches it (n,) (None: every point
    takes one), each one's clearance (m) from edges, the gap (m) under an accelerometer's base there (0 on flat
    faces, :meth:`.Surface.base_gap`) and its reach (:mod:`.reach`)."""

    points: np.ndarray
    normals: np.ndarray
    faces: np.ndarray
    excluded: dict = field(default_factory=dict)
    sensor_fit: np.ndarray | None = None
    clearance: np.ndarray | None = None
    gap: np.ndarray | None = None
    hit_fit: np.ndarray | None = None
    reach: Reach | None = None

    def sensor_points(self) -> np.ndarray:
        """Indices of the points an accelerometer fits on."""
        return np.arange(len(self)) if self.sensor_fit is None else np.flatnonzero(self.sensor_fit)

    def hit_points(self) -> np.ndarray:
        """Indices of the points the hammer reaches."""
        return np.arange(len(self)) if self.hit_fit is None else np.flatnonzero(self.hit_fit)

    def __len__(self) -> int:
        return len(self.points)

    def normal_lines(self) -> tuple[Lines, np.ndarray]:
        """One line per point along its normal, and the point index of each line."""
        return Lines(self.points, self.normals), np.arange(len(self))

    def lines(self, axes: bool) -> tuple[Lines, np.ndarray]:
        """Normal lines plus, with ``axes``, global-axis lines not parallel to the normal."""
        lines, node = self.normal_lines()
        if not axes:
            return lines, node
        extra_points, extra_dirs, extra_node = [], [], []
        for k, axis in enumerate(AXES):
            off_normal = np.abs(self.normals @ axis) < 1 - 1e-6
            extra_points.append(self.points[off_normal])
            extra_dirs.append(np.tile(axis, (off_normal.sum(), 1)))
            extra_node.append(np.flatnonzero(off_normal))
        extra = Lines(np.vstack(extra_points), np.vstack(extra_dirs))
        return lines + extra, np.concatenate([node, *extra_node])

    def block_lines(self, twists: np.ndarray) -> tuple[Lines, np.ndarray]:
        """Lines on mounting blocks along each unseen rigid motion's velocity v + ω × r at each point, in the
        surface's tangent plane, and the point index of each; none where it vanishes (a point on the axis)."""
        velocity = twists[None, :, :3] + np.cross(twists[None, :, 3:], self.points[:, None, :])  # (n, k, 3)
        velocity -= np.einsum("nkd,nd->nk", velocity, self.normals)[:, :, None] * self.normals[:, None, :]
        speed = np.linalg.norm(velocity, axis=2)
        moving = speed > UNSEEN * speed.max(initial=0.0)
        node = np.nonzero(moving)[0]
        return Lines(self.points[node], velocity[moving] / speed[moving][:, None]), node

    def triaxial_lines(self) -> tuple[Lines, np.ndarray]:
        """Three global-axis lines through every point; the point index of each line."""
        return Lines.triaxials(self.points), np.repeat(np.arange(len(self)), 3)


def thin(points: np.ndarray, radius: float) -> np.ndarray:
    """Indices of points kept, in order, so that no two kept ones are closer than ``radius``.

    Near-duplicate candidates add nothing a test can use (an accelerometer is a
    centimetre across) and slow the certificate's branch and bound.
    """
    tree = cKDTree(points)
    kept = np.ones(len(points), dtype=bool)
    for i in range(len(points)):
        if kept[i]:
            near = tree.query_ball_point(points[i], radius)
            kept[[j for j in near if j > i]] = False
    return np.flatnonzero(kept)


def largest_adjacent_face(mesh: trimesh.Trimesh) -> np.ndarray:
    """For each vertex, its largest adjacent face: a vertex candidate takes that face's
    normal, a direction one can glue or hit along (an averaged corner normal is not)."""
    adjacent = mesh.vertex_faces
    area = np.where(adjacent >= 0, mesh.area_faces[np.maximum(adjacent, 0)], -1.0)
    return adjacent[np.arange(len(adjacent)), np.argmax(area, axis=1)]


def excluded_by(points: np.ndarray, faces: np.ndarray, options: CandidateOptions) -> tuple[np.ndarray, dict]:
    """Which points (m) the boxes and faces of ``options`` exclude, and how many each took."""
    out, counts = np.zeros(len(points), dtype=bool), {}
    for lo, hi in options.exclude_boxes:
        inside = np.all((points >= np.asarray(lo)) & (points <= np.asarray(hi)), axis=1)
        counts[f"box {lo}–{hi}"] = int((inside & ~out).sum())
        out |= inside
    if options.exclude_faces:
        on = np.isin(faces, np.asarray(options.exclude_faces, dtype=int))
        counts["faces"] = int((on & ~out).sum())
        out |= on
    return out, counts


def candidate_points(
    mesh: trimesh.Trimesh, options: CandidateOptions = CandidateOptions(), surface: Surface | None = None
) -> CandidatePoints:
    """Samples, vertices and face centres of a closed mesh in metres that a sensor or a hit can use.

    Refused when the exclusions (boxes, faces) leave nothing, or when no point of the surface has the
    clearance (:mod:`.mountable`) a hit needs; then the excluded points, those short of that
    clearance and those neither the hammer nor an accelerometer reaches (:mod:`.reach`) are taken out, and
    near-duplicates.
    """
    surface = Surface.of(mesh) if surface is None else surface
    spacing = np.sqrt(mesh.area / max(options.n_samples, 1))
    samples, sample_faces = trimesh.sample.sample_surface(mesh, 4 * options.n_samples, seed=options.seed)
    inner = surface.inner_edges()
    points = np.vstack([mesh.vertices, mesh.triangles_center, mesh.vertices[inner].mean(axis=1), samples])
    faces = np.concatenate(
        [largest_adjacent_face(mesh), np.arange(len(mesh.faces)), mesh.face_adjacency[surface.inner, 0], sample_faces]
    )
    out, excluded = excluded_by(points, faces, options)
    if out.all():
        raise MasslineError(
            f"no candidate point is left on the surface after the exclusions ({excluded}); relax the keep-outs"
        )
    sensor, hit = options.clearances
    clearance = np.zeros(len(points))
    roomy = surface.roomy(faces, hit)
    clearance[roomy] = surface.clearance(points[roomy], faces[roomy], max(sensor, hit))
    fits = clearance >= hit
    if not fits.any():
        raise MasslineError(
            f"no place on the surface is flat and {1e3 * hit:.3g} mm clear of every edge, as a hammer hit needs "
            f"(it is all edges, corners, small or curved faces): give a smaller {param('options.hammer_tip')} "
            f"(or {param('options.edge_keepout')})"
        )
    excluded["edges, corners, small or curved faces"] = int((~fits & ~out).sum())
    usable = np.flatnonzero(fits & ~out)
    thinned = usable[thin(points[usable], 0.5 * spacing)]
    normals = surface.surface_normal(points[thinned], faces[thinned])
    reached = reach(mesh, points[thinned], normals, options.reach_sizes)
    excluded |= unreachable_counts(reached)
    if len(thinned) and not reached.hit.any():  # none left before the reach: the budget's refusal says so
        raise MasslineError(
            f"the hammer reaches no place on the surface: a {1e3 * options.hammer_head:.3g} mm head needs "
            f"{1e3 * options.hammer_swing:.3g} mm clear along the normal: give a smaller "
            f"{param('options.hammer_head')} or {param('options.hammer_swing')}"
        )
    either = np.flatnonzero(reached.hit | reached.sensor)
    kept, reached = thinned[either], reached.take(either)
    gap = surface.base_gap(points[kept], faces[kept], options.sensor_base)
    return CandidatePoints(
        points=points[kept],
        normals=normals[either],
        faces=faces[kept],
        excluded=excluded,
        sensor_fit=(clearance[kept] >= sensor) & (gap <= PAD_GAP) & reached.sensor,
        clearance=clearance[kept],
        gap=gap,
        hit_fit=reached.hit,
        reach=reached,
    )


@dataclass(frozen=True, eq=False)
class CandidateLines:
    """Candidates of one side: their lines; ``members`` (n, w), the lines each
    candidate is made of (one, or three for a triaxial; −1 pads); its budget
    group (0 uniaxial, 1 triaxial, ``BLOCK`` on a mounting block); and the candidate point (node) of each line."""

    lines: Lines
    members: np.ndarray
    group: np.ndarray
    node: np.ndarray

    @classmethod
    def single(cls, lines: Lines) -> "CandidateLines":
        """Every line a candidate of its own (group 0, node = its index)."""
        n = len(lines)
        return cls(lines, np.arange(n)[:, None], np.zeros(n, int), np.arange(n))

    def __len__(self) -> int:
        return len(self.members)

    def line_index(self, chosen) -> np.ndarray:
        """The lines of the chosen candidates, in order."""
        rows = self.members[np.asarray(chosen, dtype=int)].ravel()
        return rows[rows >= 0]

    def subset(self, index: np.ndarray) -> "CandidateLines":
        """The candidates ``index`` alone, with only their lines."""
        members = self.members[index]
        used = np.unique(members[members >= 0])
        remapped = np.where(members >= 0, np.searchsorted(used, np.maximum(members, 0)), -1)
        return CandidateLines(self.lines[used], remapped, self.group[index], self.node[used])

    def any_line(self, mask: np.ndarray) -> np.ndarray:
        """Per candidate: does any of its lines satisfy ``mask`` (per line)?"""
        return np.append(mask, False)[self.members].any(axis=1)


def side_lines(
    points: CandidatePoints, index: np.ndarray, axes: bool, planar: bool, triaxial: bool, twists=np.zeros((0, 6))
) -> CandidateLines:
    """One side's candidates at the points ``index``: normals (and axes, blocks along the unseen ``twists``, and
    triaxials); nodes index ``points``.

    A plate gets its out-of-plane lines only (§2.3).
    """
    at = CandidatePoints(points.points[index], points.normals[index], points.faces[index])
    if planar:
        on_faces = np.abs(at.normals[:, 2]) > 1 - 1e-6
        if on_faces.sum() < 3:
            raise MasslineError(
                "fewer than 3 candidate points on the plate's faces: relax the exclusions, or give a smaller "
                f"{param('options.sensor_base')} or {param('options.hammer_tip')}"
            )
        lines = Lines(at.points[on_faces], np.tile([0.0, 0.0, 1.0], (int(on_faces.sum()), 1)))
        return replace(CandidateLines.single(lines), node=index[on_faces])
    lines, node = at.lines(axes)
    group = np.zeros(len(lines), int)
    if len(twists) and not axes:
        blocks, block_node = at.block_lines(twists)
        lines, node = lines + blocks, np.concatenate([node, block_node])
        group = np.concatenate([group, np.full(len(blocks), BLOCK)])
    members = np.arange(len(lines))[:, None]
    if triaxial:
        tri, tri_node = at.triaxial_lines()
        members = np.vstack(
            [np.pad(members, ((0, 0), (0, 2)), constant_values=-1), len(lines) + np.arange(3 * len(at)).reshape(-1, 3)]
        )
        group = np.concatenate([group, np.ones(len(at), int)])
        lines, node = lines + tri, np.concatenate([node, tri_node])
    return CandidateLines(lines, members, group, index[node])


def candidate_lines(
    points: CandidatePoints, axes: bool, planar: bool, triaxial: bool, blocks=(np.zeros((0, 6)), np.zeros((0, 6)))
) -> tuple[CandidateLines, CandidateLines]:
    """Sensor candidates where an accelerometer fits (triaxials among them when asked), exciter candidates where
    the hammer reaches; ``axes``: mounting blocks along the global axes; ``blocks``: the rigid motions (k, 6) each side's
    normals leave unseen, read or driven on blocks along them (:func:`blocks_needed`)."""
    sensors = side_lines(points, points.sensor_points(), axes, planar, triaxial, blocks[0])
    return sensors, side_lines(points, points.hit_points(), axes, planar, False, blocks[1])


def unseen_twists(points: CandidatePoints, index: np.ndarray) -> np.ndarray:
    """The rigid motions (k, 6), twists (v, ω) at the origin, that no surface normal at the points ``index`` reads
    better than with an arm of ``UNSEEN`` of the body's size (a line (d, r × d) reads d · (v + ω × r)): among the
    right singular vectors of their coordinates (arms in units of the body's size), those whose best reading is
    below it. A surface of revolution's normals all meet its axis: rotation about it (k = 1); a sphere's, its
    centre (k = 3). A thin plate's in-plane motions are seen, by its rims."""
    coords = Lines(points.points[index], points.normals[index]).coordinates
    size = max(np.ptp(points.points, axis=0).max(initial=0.0), 1e-300)  # m, the body's extent
    scale = np.array([1, 1, 1, size, size, size])
    twists = np.linalg.svd(coords / scale, full_matrices=False)[2]  # (6, 6): the n × n left factor is not needed
    best = np.abs(coords / scale @ twists.T).max(axis=0, initial=0.0)
    unseen = twists[best < UNSEEN] / scale
    return unseen / np.linalg.norm(unseen, axis=1, keepdims=True)


def blocks_needed(points: CandidatePoints, planar: bool, triaxial: bool) -> tuple[np.ndarray, np.ndarray]:
    """The rigid motion (1, 6) the accelerometers' normals leave unseen (none when triaxials are planned: they see
    all) and the one no hit's normal drives (:func:`unseen_twists`), read or driven on mounting blocks: a turned
    part's rotation about its axis. Where the normals miss more than ``MOST_BLOCKED`` motions (a sphere, one flat
    face) the part offers too little for uniaxial lines and none is offered: the planner refuses, naming
    ``--triaxial`` and ``--axes``. A plate needs none (§2.3)."""
    none = np.zeros((0, 6))
    if planar:
        return none, none

    def offered(index: np.ndarray) -> np.ndarray:
        unseen = unseen_twists(points, index) if len(index) else none
        return unseen if len(unseen) <= MOST_BLOCKED else none

    return (none if triaxial else offered(points.sensor_points())), offered(points.hit_points())
