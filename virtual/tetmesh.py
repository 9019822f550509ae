"""Tetrahedral meshes of a closed surface, by netgen (LGPL, pip ``netgen-mesher``).

The surface goes to netgen as an ASCII STL with 17 significant digits, so its
vertices reach the mesher exactly (binary STL would round them to float32) and
the tetrahedra fill the same polyhedron: their volume equals the surface's to
rounding. netgen is imported only when a mesh is made.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from massline.core.errors import MasslineError, param
from massline.meshes.loader import validate_solid

if TYPE_CHECKING:  # trimesh loads where a surface is read, not for every command that imports this
    import trimesh

SIZE_PER_THICKNESS = 4.0  # element size / mean thickness 2V/A
SPANS = 16  # elements, at least, along the largest extent
MAX_DOFS = 25_000  # quadratic-tetrahedron DOFs the default size stays under (the estimate runs ~30 % low)
GRADING = 0.3  # netgen's default: how fast elements may grow away from a small feature
FEATURE_DOFS = 2 * MAX_DOFS  # a default mesh beyond this was refined by small features: meshed again, graded faster
FEATURE_GRADING = 0.6  # featuretype.STL: 78 400 → 42 300 DOF, its first 3 modes +0.36 %, +0.29 %, +0.56 %
CURVE_ANGLE = 0.7  # rad of a curve one element may span: its chord then lies within 6 % of the radius
MOUNTABLE_RADIUS = 12.5e-3  # m: curves this round hold a 10 mm accelerometer base on a 1 mm pad (placement's
# SENSOR_BASE² / (8 PAD_GAP), restated: the simulator imports nothing of placement, tests/test_effects_registry.py)
CREASE_DEG = (1.0, 30.0)  # degrees between neighbouring facets of a tessellated curve (sharper: an edge, as
# placement's SHARP_EDGE_DEG)
DOFS_PER_VOLUME, DOFS_PER_AREA = 4.8, 21.0  # fitted n_dofs ≈ 4.8 V/h³ + 21 A/h² (netgen, P2; ±30 %)
FACET = "facet normal 0 0 0\nouter loop\n" + "vertex %.17g %.17g %.17g\n" * 3 + "endloop\nendfacet\n"  # ASCII STL facet


def size_for_dofs(mesh: trimesh.Trimesh, n_dofs: float) -> float:
    """The element size h (m) at which about ``n_dofs`` quadratic DOFs fill the solid.

    The positive root of n h³ − 21 A h − 4.8 V = 0 (A: surface area, m²; V:
    volume, m³), fitted on netgen meshes of plates, bars, brackets, a cube and
    a cylinder with 600–100 000 DOF.
    """
    roots = np.roots([n_dofs, 0.0, -DOFS_PER_AREA * mesh.area, -DOFS_PER_VOLUME * mesh.volume])
    return float(roots[np.isreal(roots)].real.max())


def curve_radii(mesh: trimesh.Trimesh) -> np.ndarray:
    """The radius of curvature (m) across each soft crease of a tessellated curve (facets meeting at
    ``CREASE_DEG``): the mean width of its two facets, across their shared edge, over the angle between them
    (exact for a cylinder's facets)."""
    angles = mesh.face_adjacency_angles
    soft = (angles > np.radians(CREASE_DEG[0])) & (angles < np.radians(CREASE_DEG[1]))
    edges = mesh.vertices[mesh.face_adjacency_edges[soft]]  # (k, 2, 3)
    far = mesh.vertices[mesh.face_adjacency_unshared[soft]] - edges[:, :1]  # each facet's third vertex (k, 2, 3)
    along = (edges[:, 1] - edges[:, 0]) / np.linalg.norm(edges[:, 1] - edges[:, 0], axis=1, keepdims=True)
    across = far - np.einsum("kjd,kd->kj", far, along)[:, :, None] * along[:, None, :]
    return np.linalg.norm(across, axis=2).mean(axis=1) / angles[soft]


def default_size(mesh: trimesh.Trimesh) -> float:
    """Default element size h (m): ``min(4 · 2V/A, L/16)``, at most ``CURVE_ANGLE`` of the smallest curve
    that holds an accelerometer (radius ≥ ``MOUNTABLE_RADIUS``: a point planned on the surface then lies within
    ``elastic.OUTSIDE`` of the meshed solid), coarsened to stay near 25 000 DOF.

    ``2V/A`` (volume V, surface area A) is the body's mean thickness: a plate's
    thickness, half a square bar's side, a third of a cube's side. Four times it
    puts one layer of flat quadratic tetrahedra through a plate and a few
    across a bar, enough for their bending; ``L/16`` (L: largest extent) keeps
    sixteen elements along chunky bodies, whose walls are not thin against their
    span. The size never goes below ``size_for_dofs(mesh, 25 000)``, which keeps
    the model near 25 000 DOF where the surface's features are not smaller than the
    size (where they are, :func:`default_tetrahedra` grades the mesh faster; the plate
    row below shows what 29 000 DOF already resolve).

    Measured with quadratic tetrahedra (scikit-fem, :mod:`.elastic`), first
    elastic frequencies against closed forms or much finer meshes:

    ==============================  =====  ======  =================================================
    body                            h, mm  DOF     first elastic frequencies against
    ==============================  =====  ======  =================================================
    steel bar 0.8 × 0.01 × 0.01 m   19.9   2 300   Euler–Bernoulli, 2 pairs: −0.03 %, −0.07 %
    Al plate 0.3 × 0.3 × 0.003 m    11.8   28 800  Leissa, 3 modes: −0.11 %, +0.05 %, +0.07 %
    Al plate 0.3 × 0.3 × 0.006 m    18.8   10 900  Leissa, 3 modes: −0.31 %, +0.01 %, +0.06 %
    bundled plate                   18.8   5 500   72 000-DOF mesh, 4 modes: +0.3 % … +1.3 %
    bundled structure               10.0   18 300  188 000-DOF mesh, 4 modes: +0.7 % … +1.3 %
    bundled bracket                 9.0    7 200   38 000-DOF mesh, 4 modes: +0.9 % … +1.4 %
    ==============================  =====  ======  =================================================
    """
    extents = np.ptp(mesh.vertices, axis=0)
    radii = curve_radii(mesh)
    curve = CURVE_ANGLE * radii[radii >= MOUNTABLE_RADIUS].min(initial=np.inf)
    size = min(SIZE_PER_THICKNESS * 2.0 * mesh.volume / mesh.area, extents.max() / SPANS, curve)
    return float(max(size, size_for_dofs(mesh, MAX_DOFS)))


def _write_ascii_stl(mesh: trimesh.Trimesh, path: Path) -> None:
    """ASCII STL with "%.17g" coordinates, so netgen reads the vertices exactly."""
    facets = (FACET * len(mesh.faces)) % tuple(mesh.triangles.ravel())
    path.write_text(f"solid surface\n{facets}endsolid surface\n")


def _positively_oriented(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The tetrahedra with two vertices swapped wherever their signed volume is negative."""
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets = tets.copy()
    tets[negative, 1], tets[negative, 2] = tets[negative, 2], tets[negative, 1].copy()
    return tets


def _netgen_mesh(mesh: trimesh.Trimesh, size: float, grading: float):
    """netgen's volume mesh of the surface (m) with largest edge ``size`` (m), elements growing away from small
    features at ``grading``, silently."""
    import netgen.meshing
    from netgen.stl import STLGeometry

    netgen.meshing.SetMessageImportance(0)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "surface.stl"
        _write_ascii_stl(mesh, path)
        return STLGeometry(str(path)).GenerateMesh(maxh=size, grading=grading)


def tetrahedralise(
    mesh: trimesh.Trimesh, size: float, name: str = "the surface", grading: float = GRADING
) -> tuple[np.ndarray, np.ndarray]:
    """Positively oriented tetrahedra filling a closed surface.

    Parameters
    ----------
    mesh
        Closed, outward-wound surface, in metres in the body frame O xyz.
    size
        Largest element edge length (m), netgen's ``maxh``.
    name
        What to call the surface in error messages.
    grading
        netgen's grading, 0 to 1: how fast elements grow away from features smaller than ``size``.

    Returns
    -------
    points
        Vertex coordinates (n, 3), m, frame O xyz.
    tets
        Vertex indices (k, 4) of positively oriented tetrahedra.
    """
    if not size > 0:
        raise MasslineError(f"element size {size} m is not positive: give a positive {param('size')}")
    validate_solid(mesh, name)  # netgen loops forever on some open surfaces
    try:
        result = _netgen_mesh(mesh, size, grading)
        points = np.array(result.Coordinates(), dtype=float)
        tets = result.Elements3D().NumPy()["nodes"][:, :4].astype(np.int64) - 1
    except Exception as err:  # netgen raises plain Exceptions with C++ messages
        raise MasslineError(
            f"tetrahedral meshing of {name} failed: {' '.join(str(err).split()) or type(err).__name__}; "
            f"check that the surface is closed or try a different {param('size')}"
        ) from None
    if len(tets) == 0:
        raise MasslineError(
            f"tetrahedral meshing of {name} gave no tetrahedra; check that the surface is closed "
            f"or try a different {param('size')}"
        )
    return points, _positively_oriented(points, tets)


def quadratic_dofs(points: np.ndarray, tets: np.ndarray) -> int:
    """The DOFs of quadratic tetrahedra on the mesh: three per vertex and per edge."""
    edges = np.sort(tets[:, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]], axis=2).reshape(-1, 2)
    return 3 * (len(points) + len(np.unique(edges, axis=0)))


def default_tetrahedra(mesh: trimesh.Trimesh, name: str = "the surface") -> tuple[float, np.ndarray, np.ndarray]:
    """The default size (:func:`default_size`) and its tetrahedra; where features smaller than the size refine
    them past ``FEATURE_DOFS`` (a machined part's small holes and chamfers), meshed again at ``FEATURE_GRADING``:
    the solve's time grows faster than the DOFs, its frequencies change by a fraction of a percent."""
    size = default_size(mesh)
    points, tets = tetrahedralise(mesh, size, name)
    if quadratic_dofs(points, tets) > FEATURE_DOFS:
        points, tets = tetrahedralise(mesh, size, name, FEATURE_GRADING)
    return size, points, tets
