"""Candidate points and lines on a body's surface, as a technician can use them.

Points: the mesh vertices, the face centres and area-uniform samples, about
``n_samples`` over the surface, thinned so that no two are closer than half the
mean spacing; each with the outward normal of the face it lies on. Lines
at each point: the surface normal (a hammer hit, a uniaxial accelerometer
glued on the face) and, optionally, the three global axes (mounting blocks).
A triaxial accelerometer is one candidate of three global-axis lines through a
point. Regions can be excluded (boxes, faces, a keep-out distance from sharp
edges).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import trimesh
from scipy.spatial import cKDTree

from massline.placement.errors import MasslineError
from massline.placement.lines import AXES, Lines

SHARP_EDGE_DEG = 30.0  # a crease sharper than this is an edge a sensor should keep away from


@dataclass(frozen=True)
class CandidateOptions:
    """What may be used, in metres in the mesh frame.

    ``exclude_boxes``: ((lo, hi), ...) regions with no candidate;
    ``exclude_faces``: face indices with no candidate;
    ``edge_keepout``: distance (m) to keep from sharp edges;
    ``axes``: add the global axes as line directions (mounting blocks).
    """

    n_samples: int = 400
    axes: bool = False
    exclude_boxes: tuple = ()
    exclude_faces: tuple = ()
    edge_keepout: float = 0.0
    seed: int = 0


@dataclass(frozen=True, eq=False)
class CandidatePoints:
    """Points (n, 3) m, outward normals (n, 3), the face each lies on (n,)."""

    points: np.ndarray
    normals: np.ndarray
    faces: np.ndarray
    excluded: dict = field(default_factory=dict)

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

    def triaxial_lines(self) -> tuple[Lines, np.ndarray]:
        """Three global-axis lines through every point; the point index of each line."""
        return Lines.triaxials(self.points), np.repeat(np.arange(len(self)), 3)


def sharp_edges(mesh: trimesh.Trimesh, degrees: float = SHARP_EDGE_DEG) -> np.ndarray:
    """End points (k, 2, 3) of the edges where the surface creases more than ``degrees``."""
    sharp = mesh.face_adjacency_angles > np.radians(degrees)
    return mesh.vertices[mesh.face_adjacency_edges[sharp]]


def distance_to_segments(points: np.ndarray, segments: np.ndarray, chunk: int = 2048) -> np.ndarray:
    """Distance from each point to the nearest of the segments (k, 2, 3)."""
    if len(segments) == 0:
        return np.full(len(points), np.inf)
    a, b = segments[:, 0], segments[:, 1]
    ab = b - a
    length2 = np.maximum(np.einsum("kd,kd->k", ab, ab), 1e-300)
    out = np.empty(len(points))
    for start in range(0, len(points), chunk):
        p = points[start : start + chunk, None, :]
        t = np.clip(np.einsum("nkd,kd->nk", p - a, ab) / length2, 0, 1)
        nearest = a + t[..., None] * ab
        out[start : start + chunk] = np.linalg.norm(p - nearest, axis=2).min(axis=1)
    return out


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


def candidate_points(mesh: trimesh.Trimesh, options: CandidateOptions = CandidateOptions()) -> CandidatePoints:
    """Samples, vertices and face centres of a closed mesh in metres, after exclusions."""
    spacing = np.sqrt(mesh.area / max(options.n_samples, 1))
    samples, sample_faces = trimesh.sample.sample_surface(mesh, 4 * options.n_samples, seed=options.seed)
    points = np.vstack([mesh.vertices, mesh.triangles_center, samples])
    faces = np.concatenate([largest_adjacent_face(mesh), np.arange(len(mesh.faces)), sample_faces])
    first = thin(points, 0.5 * spacing)
    points, faces = points[first], faces[first]
    normals = mesh.face_normals[faces]
    keep = np.ones(len(points), dtype=bool)
    excluded = {}
    for lo, hi in options.exclude_boxes:
        inside = np.all((points >= np.asarray(lo)) & (points <= np.asarray(hi)), axis=1)
        excluded[f"box {lo}–{hi}"] = int((inside & keep).sum())
        keep &= ~inside
    if options.exclude_faces:
        on = np.isin(faces, np.asarray(options.exclude_faces, dtype=int))
        excluded["faces"] = int((on & keep).sum())
        keep &= ~on
    if options.edge_keepout > 0:
        near = distance_to_segments(points, sharp_edges(mesh)) < options.edge_keepout
        excluded["edge keep-out"] = int((near & keep).sum())
        keep &= ~near
    if not keep.any():
        raise MasslineError(
            f"no candidate point is left on the surface after the exclusions ({excluded}); relax the keep-outs"
        )
    return CandidatePoints(points[keep], normals[keep], faces[keep], excluded)


@dataclass(frozen=True, eq=False)
class CandidateLines:
    """Candidates of one side: their lines; ``members`` (n, w), the lines each
    candidate is made of (one, or three for a triaxial; −1 pads); its budget
    group (0 uniaxial, 1 triaxial); and the candidate point (node) of each line."""

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


def candidate_lines(
    points: CandidatePoints, axes: bool, planar: bool, triaxial: bool
) -> tuple[CandidateLines, CandidateLines]:
    """Sensor and exciter candidates at the points: normals (and axes), triaxials for sensors.

    A plate gets its out-of-plane lines only (§2.3), the same for both sides.
    """
    if planar:
        on_faces = np.abs(points.normals[:, 2]) > 1 - 1e-6
        if on_faces.sum() < 3:
            raise MasslineError("fewer than 3 candidate points on the plate's faces: relax the exclusions")
        pts = points.points[on_faces]
        lines = Lines(pts, np.tile([0.0, 0.0, 1.0], (len(pts), 1)))
        side = replace(CandidateLines.single(lines), node=np.flatnonzero(on_faces))
        return side, side
    lines, node = points.lines(axes)
    members = np.arange(len(lines))[:, None]
    group = np.zeros(len(lines), int)
    sensor_lines, sensor_node = lines, node
    if triaxial:
        tri, tri_node = points.triaxial_lines()
        offset = len(lines)
        members = np.vstack(
            [np.pad(members, ((0, 0), (0, 2)), constant_values=-1), offset + np.arange(3 * len(points)).reshape(-1, 3)]
        )
        group = np.concatenate([group, np.ones(len(points), int)])
        sensor_lines, sensor_node = lines + tri, np.concatenate([node, tri_node])
    return CandidateLines(sensor_lines, members, group, sensor_node), replace(CandidateLines.single(lines), node=node)
