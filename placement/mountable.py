"""Where an accelerometer can be glued and a hammer can strike square: flat patches and feature edges.

A *flat patch* is a connected set of coplanar triangles (neighbours whose normals differ by less than
``FLAT_DEG``). A *feature edge* is a mesh edge where the surface creases by more than ``SHARP_EDGE_DEG``,
or an edge with one triangle only. The *clearance* of a point on a patch is

    clearance(p) = min( dist(p, boundary segments of its patch), dist(p, feature edges) ),

the radius of the largest disk around p, in the patch's plane, that stays inside the patch and keeps
that far from every feature edge in space (a rim above a pocket's floor counts). An accelerometer with
a base B across fits where clearance ≥ B/2; a hammer tip T across strikes square where clearance ≥ T/2.

A *soft crease* (less than ``SHARP_EDGE_DEG``: a tessellated cylinder's side, a fillet, a shallow bend) bounds
no patch for the clearance: flat patches joined across soft creases are one *smooth region*. A hammer tip
strikes anywhere on it clear of sharp edges, along its own triangle's normal. An accelerometer's flat base
on a curved region stands off the surface by its *gap*,

    gap(p) = max_rim |(r − q)·n_q|,   r = p + (B/2)(cos φ u + sin φ v),

r the base's rim in the plane of p's triangle, q the surface point of p's region nearest to r and n_q its
triangle's normal ((B/2)²/(2R) on a radius R: 0.31 mm for a 10 mm base on R 40 mm). It is glued directly where
the gap is at most ``FILM_GAP`` (an adhesive film fills it), on a cemented pad up to ``PAD_GAP``, and not at
all beyond. All lengths in metres, mesh frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import trimesh
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from massline.core.errors import MasslineError

FLAT_DEG = 0.5  # neighbouring triangles closer than this to coplanar belong to one flat patch
TANGENT = 3.0  # a flat patch this many times wider than the others at a vertex is a face a fillet meets tangentially
SHARP_EDGE_DEG = 30.0  # a crease sharper than this is an edge a sensor or a hit keeps away from; softer, no bound
FILM_GAP = 0.1e-3  # m: the largest gap under a base that a film of adhesive or wax fills
PAD_GAP = 1.0e-3  # m: the largest a cemented pad under the base fills (a 10 mm base on R 12.5 mm)
RIM_POINTS = 16  # points on a base's rim where its gap is measured
GAP_SAMPLES = 200_000  # at most this many surface samples of the curved regions (spacing base/8 or coarser)
PIECES_PER_SIZE = 200  # long edges are cut into pieces no longer than the body's size / this, for the search
SNAP_TOLERANCE = 2e-3  # m: a fixed sensor or hit given farther than this from the surface is refused


def plane_bases(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (n, 3) each, orthogonal to each other and to the unit ``normals`` (n, 3)."""
    helper = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(normals, helper)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    return u, np.cross(normals, u)


def foot_on_segments(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The point (n, 3) of each segment a–b (n, 3) nearest to the point (n, 3) of the same row."""
    ab = b - a
    t = np.clip(np.einsum("nd,nd->n", points - a, ab) / np.maximum(np.einsum("nd,nd->n", ab, ab), 1e-300), 0, 1)
    return a + t[:, None] * ab


def feature_edges(mesh: trimesh.Trimesh, degrees: float = SHARP_EDGE_DEG) -> np.ndarray:
    """End points (k, 2, 3) of the edges creasing more than ``degrees`` and of the edges with one triangle."""
    sharp = mesh.face_adjacency_edges[mesh.face_adjacency_angles > np.radians(degrees)]
    unique, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    return mesh.vertices[np.vstack([sharp, unique[counts == 1]])]


def soft_creases(mesh: trimesh.Trimesh) -> np.ndarray:
    """Which face adjacencies (mesh.face_adjacency rows) crease by less than ``SHARP_EDGE_DEG``: inside a smooth
    region (the facets of a tessellated curve, a fillet), not an edge."""
    return mesh.face_adjacency_angles < np.radians(SHARP_EDGE_DEG)


def flat_patches(mesh: trimesh.Trimesh, degrees: float = FLAT_DEG) -> np.ndarray:
    """The flat patch of each face (n_faces,): connected components of nearly coplanar neighbours."""
    pairs = mesh.face_adjacency[mesh.face_adjacency_angles < np.radians(degrees)]
    graph = trimesh.graph.edges_to_coo(pairs, count=len(mesh.faces))
    return connected_components(graph, directed=False)[1]


def pieces(segments: np.ndarray, length: float) -> np.ndarray:
    """The segments (k, 2, 3) cut into equal pieces no longer than ``length`` (m), with the source of each."""
    counts = np.maximum(np.ceil(np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1) / length), 1).astype(int)
    source = np.repeat(np.arange(len(segments)), counts)
    k = np.arange(len(source)) - np.repeat(np.cumsum(counts) - counts, counts)
    t0, t1 = k / counts[source], (k + 1) / counts[source]
    a, b = segments[source, 0], segments[source, 1]
    return np.stack([a + t0[:, None] * (b - a), a + t1[:, None] * (b - a)], axis=1), source


@dataclass(frozen=True, eq=False)
class Surface:
    """A closed mesh (m) with its flat patches and the segments a mounted point keeps clear of.

    ``patch``: patch of each face; ``segments`` (k, 2, 3): patch boundaries and feature edges;
    ``owner`` (k,): the patch a boundary segment bounds, −1 for a feature edge (it bounds every patch).
    """

    mesh: trimesh.Trimesh
    patch: np.ndarray
    segments: np.ndarray
    owner: np.ndarray

    @classmethod
    def of(cls, mesh: trimesh.Trimesh) -> "Surface":
        patch = flat_patches(mesh)
        adjacent = patch[mesh.face_adjacency]
        between = (adjacent[:, 0] != adjacent[:, 1]) & ~soft_creases(mesh)
        edges = mesh.vertices[mesh.face_adjacency_edges[between]]
        features = feature_edges(mesh)
        return cls(
            mesh,
            patch,
            np.concatenate([edges, edges, features]),
            np.concatenate([adjacent[between, 0], adjacent[between, 1], np.full(len(features), -1)]),
        )

    @property
    def inner(self) -> np.ndarray:
        """Which face adjacencies (mesh.face_adjacency rows) lie inside one flat patch."""
        pairs = self.patch[self.mesh.face_adjacency]
        return pairs[:, 0] == pairs[:, 1]

    def inner_edges(self) -> np.ndarray:
        """Vertex pairs (k, 2) of the edges inside flat patches."""
        return self.mesh.face_adjacency_edges[self.inner]

    @property
    def size(self) -> float:
        """Largest extent of the body, m."""
        return float(self.mesh.extents.max())

    @cached_property
    def smooth(self) -> tuple[np.ndarray, np.ndarray]:
        """The smooth region of each face (its flat patches joined across soft creases) and each region's area
        (m²)."""
        mesh = self.mesh
        pairs = mesh.face_adjacency[soft_creases(mesh)]
        region = connected_components(trimesh.graph.edges_to_coo(pairs, count=len(mesh.faces)), directed=False)[1]
        return region, np.bincount(region, weights=mesh.area_faces)

    def roomy(self, faces: np.ndarray, radius: float) -> np.ndarray:
        """Whether the smooth region of each face (n,) is large enough to hold a disk of ``radius`` (m) at all."""
        region, area = self.smooth
        return area[region[faces]] >= np.pi * radius**2

    @cached_property
    def curved(self) -> np.ndarray:
        """Whether each face (n_faces,) lies in a curved smooth region: one of more than one flat patch."""
        region = self.smooth[0]
        patches = np.unique(np.column_stack([region, self.patch]), axis=0)[:, 0]
        return np.bincount(patches, minlength=region.max() + 1)[region] > 1

    def base_gap(self, points: np.ndarray, faces: np.ndarray, base: float) -> np.ndarray:
        """The gap (m) under a flat base ``base`` across (m) at points (n, 3) on ``faces`` (n,), in their
        triangles' planes: the largest distance of its rim from its region's surface (0 on a flat region)."""
        gap = np.zeros(len(points))
        on = np.flatnonzero(self.curved[faces])
        if not len(on):
            return gap
        region = self.smooth[0]
        samples, which, tree = self.curve_samples(base)
        normal = self.mesh.face_normals[faces[on]]
        u, v = plane_bases(normal)
        phi = 2 * np.pi * np.arange(RIM_POINTS) / RIM_POINTS
        rim = points[on, None, :] + base / 2 * (np.cos(phi)[:, None] * u[:, None] + np.sin(phi)[:, None] * v[:, None])
        lifted = np.repeat(self.lift(region[faces[on]]), RIM_POINTS)
        nearest = tree.query(np.column_stack([rim.reshape(-1, 3), lifted]))[1]
        off = np.einsum("kd,kd->k", rim.reshape(-1, 3) - samples[nearest], self.mesh.face_normals[which[nearest]])
        gap[on] = np.abs(off).reshape(-1, RIM_POINTS).max(axis=1)
        return gap

    def curve_samples(self, base: float) -> tuple[np.ndarray, np.ndarray, cKDTree]:
        """Points (k, 3) m sampled on the curved regions about an eighth of ``base`` (m) apart, and their faces'
        centres; the face of each (k,); a k-d tree of them lifted by their smooth region (kept per base)."""
        if base not in self.sample_cache:
            region, sampled = self.smooth[0], self.curved
            area = self.mesh.area_faces[sampled].sum()
            count = int(min(GAP_SAMPLES, max(area / (base / 8) ** 2, 1000)))
            submesh = self.mesh.submesh([np.flatnonzero(sampled)], append=True)
            samples, which = trimesh.sample.sample_surface_even(submesh, count, seed=0)
            samples = np.vstack([samples, self.mesh.triangles_center[sampled]])
            which = np.concatenate([np.flatnonzero(sampled)[which], np.flatnonzero(sampled)])
            self.sample_cache[base] = samples, which, cKDTree(np.column_stack([samples, self.lift(region[which])]))
        return self.sample_cache[base]

    @cached_property
    def sample_cache(self) -> dict:
        return {}

    def onto_region(self, point: np.ndarray, region: int) -> tuple[np.ndarray, int]:
        """The point (3,) m of smooth region ``region`` nearest to ``point`` (3,), and the face it lies on."""
        faces = np.flatnonzero(self.smooth[0] == region)
        feet = trimesh.triangles.closest_point(self.mesh.triangles[faces], np.tile(point, (len(faces), 1)))
        k = int(np.argmin(np.linalg.norm(feet - point, axis=1)))
        return feet[k], int(faces[k])

    def normal(self, faces: np.ndarray) -> np.ndarray:
        """Outward unit normal (n, 3) of the faces' patches (that of the face: a patch is flat)."""
        return self.mesh.face_normals[faces]

    @cached_property
    def patch_width(self) -> np.ndarray:
        """Each flat patch's width (m): twice its area over its perimeter (a strip w wide and long: w)."""
        mesh = self.mesh
        area = np.bincount(self.patch, weights=mesh.area_faces)
        pairs = self.patch[mesh.face_adjacency]
        between = pairs[:, 0] != pairs[:, 1]
        ends = mesh.vertices[mesh.face_adjacency_edges[between]]
        length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
        perimeter = np.bincount(pairs[between].ravel(), weights=np.repeat(length, 2), minlength=len(area))
        return 2 * area / np.maximum(perimeter, 1e-300)

    @cached_property
    def corner_normals(self) -> np.ndarray:
        """Each face's three corner normals (n_faces, 3, 3): at each vertex the angle-weighted mean of the normals
        of the faces around it in the same smooth region (the surface the facets tessellate, not its facets); where
        one flat patch there is ``TANGENT`` times wider than every other (a face that a fillet's narrow facets meet
        tangentially), that patch's normal, which the surface has along the tangent edge."""
        mesh, region = self.mesh, self.smooth[0]
        key = np.column_stack([np.repeat(region, 3), mesh.faces.ravel()])
        _, corner = np.unique(key, axis=0, return_inverse=True)
        corner = corner.ravel()
        weighted = mesh.face_normals[:, None, :] * mesh.face_angles[:, :, None]
        total = np.zeros((corner.max() + 1, 3))
        np.add.at(total, corner, weighted.reshape(-1, 3))
        patch = np.repeat(self.patch, 3)
        width = self.patch_width[patch]
        widest = np.zeros(len(total))
        np.maximum.at(widest, corner, width)
        first = np.full(len(total), len(corner))
        np.minimum.at(first, corner, np.where(width == widest[corner], np.arange(len(corner)), len(corner)))
        other = np.zeros(len(total))
        np.maximum.at(other, corner, np.where(patch != patch[first[corner]], width, 0.0))
        tangent = (other > 0) & (widest >= TANGENT * other)
        total[tangent] = mesh.face_normals[first[tangent] // 3]
        total /= np.maximum(np.linalg.norm(total, axis=1, keepdims=True), 1e-300)
        return total[corner.reshape(-1, 3)]

    def surface_normal(self, points: np.ndarray, faces: np.ndarray) -> np.ndarray:
        """Outward unit normal (n, 3) of the smooth surface at points (n, 3) on ``faces`` (n,): the face's on a
        flat region, its corner normals interpolated (barycentric) on a curved one (a cylinder's radius)."""
        normal = self.mesh.face_normals[faces].copy()
        on = np.flatnonzero(self.curved[faces])
        if len(on):
            weights = trimesh.triangles.points_to_barycentric(self.mesh.triangles[faces[on]], points[on])
            smooth = np.einsum("nk,nkd->nd", weights, self.corner_normals[faces[on]])
            normal[on] = smooth / np.linalg.norm(smooth, axis=1, keepdims=True)
        return normal

    @property
    def piece_length(self) -> float:
        """Length (m) of the pieces the segments are cut into for the search."""
        return self.size / PIECES_PER_SIZE

    @cached_property
    def searches(self) -> list[tuple[np.ndarray, cKDTree]]:
        """Pieces of the patch boundaries (searched with the patch as a fourth coordinate, far apart, so that a
        point meets its own patch's only) and of the feature edges (met by every point): ends, tree."""
        cut, source = pieces(self.segments, self.piece_length)
        owner = self.owner[source]
        bounds, features = cut[owner >= 0], cut[owner < 0]
        lifted = np.column_stack([bounds.mean(axis=1), self.lift(owner[owner >= 0])])
        return [(bounds, cKDTree(lifted)), (features, cKDTree(features.mean(axis=1).reshape(-1, 3)))]

    def lift(self, patch: np.ndarray) -> np.ndarray:
        """The fourth coordinate (m) of a patch: patches lie 10 body sizes apart."""
        return 10.0 * self.size * patch

    def nearest(self, points: np.ndarray, faces: np.ndarray, reach: float) -> tuple[np.ndarray, np.ndarray]:
        """Clearance (m) of points (n, 3) lying on ``faces`` (n,) and the nearest point (n, 3) of what bounds it;
        exact below ``reach``, beyond it ``reach`` and NaN.

        Exact search: with d₀ the distance to the nearest piece midpoint, the nearest piece (length ≤ L)
        has its midpoint within d₀ + L/2, so only the pieces a k-d tree finds there are measured.
        """
        out, where = np.full(len(points), float(reach)), np.full((len(points), 3), np.nan)
        lifted = np.column_stack([points, self.lift(self.patch[faces])])
        half = self.piece_length / 2
        for (cut, tree), query in zip(self.searches, (lifted, points)):
            if not len(cut):
                continue
            d0 = tree.query(query, distance_upper_bound=reach + half)[0]
            near = np.flatnonzero(np.isfinite(d0))
            found = tree.query_ball_point(query[near], d0[near] + half)
            i = np.repeat(near, [len(f) for f in found])
            j = np.concatenate([np.asarray(f, dtype=int) for f in found]) if len(found) else np.zeros(0, int)
            foot = foot_on_segments(points[i], cut[j, 0], cut[j, 1])
            distance = np.linalg.norm(points[i] - foot, axis=1)
            order = np.lexsort((distance, i))
            first = order[np.r_[True, i[order][1:] != i[order][:-1]]] if len(order) else order
            closer = first[distance[first] < out[i[first]]]
            out[i[closer]], where[i[closer]] = distance[closer], foot[closer]
        return out, where

    def clearance(self, points: np.ndarray, faces: np.ndarray, reach: float) -> np.ndarray:
        """Clearance (m) of points (n, 3) lying on ``faces`` (n,): exact below ``reach``, ``reach`` beyond it."""
        return self.nearest(points, faces, reach)[0]

    def locate(self, point: np.ndarray, patch: int) -> int:
        """The face of ``patch`` under ``point`` (m, in the patch's plane), or −1 when it lies outside the patch."""
        faces = np.flatnonzero(self.patch == patch)
        triangles = self.mesh.triangles[faces]
        barycentric = trimesh.triangles.points_to_barycentric(triangles, np.tile(point, (len(faces), 1)))
        inside = np.flatnonzero(np.all(barycentric >= -1e-9, axis=1))
        return int(faces[inside[0]]) if len(inside) else -1


def closest_on_surface(mesh: trimesh.Trimesh, point: np.ndarray) -> tuple[np.ndarray, int]:
    """The point (3,) of the surface nearest to ``point`` (3,), m, and the face it lies on: the nearest of each
    triangle's nearest."""
    feet = trimesh.triangles.closest_point(mesh.triangles, np.tile(point, (len(mesh.faces), 1)))
    face = int(np.argmin(np.linalg.norm(feet - point, axis=1)))
    return feet[face], face


def snap(
    mesh: trimesh.Trimesh, points: np.ndarray, what: str, scale: float = 1.0, tolerance: float = SNAP_TOLERANCE
) -> np.ndarray:
    """The nearest surface points (n, 3) m to ``points`` (m); refuses one farther than ``tolerance`` (m),
    naming it in the user's length unit of ``scale`` m (as given, e.g. 0.0254 for inches)."""
    points = np.atleast_2d(points)
    nearest = np.array([closest_on_surface(mesh, p)[0] for p in points]).reshape(-1, 3)
    distance = np.linalg.norm(nearest - points, axis=1)
    far = np.flatnonzero(distance > tolerance)
    if len(far):
        k = int(far[0])
        where = ", ".join(f"{c / scale:.4g}" for c in points[k])
        raise MasslineError(
            f"{what} {k + 1} at ({where}) is {1e3 * distance[k]:.3g} mm from the body's surface (more than "
            f"{1e3 * tolerance:g} mm; nearest surface point ({', '.join(f'{c / scale:.4g}' for c in nearest[k])})): "
            "give a point on the surface, in the mesh's units"
        )
    return nearest
