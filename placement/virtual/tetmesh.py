"""Tetrahedral meshes of a closed surface, by netgen (LGPL, pip ``netgen-mesher``).

The surface goes to netgen as an ASCII STL with 17 significant digits, so its
vertices reach the mesher exactly (binary STL would round them to float32) and
the tetrahedra fill the same polyhedron: their volume equals the surface's to
rounding. netgen is imported only when a mesh is made.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import trimesh

from ..errors import MasslineError

SIZE_PER_THICKNESS = 3.0  # element size / mean thickness 2V/A
MAX_DOFS = 60_000  # quadratic-tet DOFs the default size aims to stay under
DOFS_PER_VOLUME = 60.0  # measured P2 vector DOFs per h³ of solid (netgen, bundled meshes)


def default_size(mesh: trimesh.Trimesh) -> float:
    """Default element size (m): ``3 · 2V/A``, made coarser if it would exceed ~60k DOF.

    ``2V/A`` (volume V, surface area A) is a body's mean thickness: the
    thickness of a plate, half the side of a square bar, a third of a cube's
    side. Three times it gives one layer of flat quadratic tetrahedra through
    a plate and a few across a bar, which is enough for bending; the cap
    ``h ≥ (60 V / 60 000)^(1/3)`` keeps the model below about 60 000 DOF.

    Measured with quadratic tetrahedra (P2), against closed forms:
    """
    mean_thickness = 2.0 * mesh.volume / mesh.area
    dof_limited = (DOFS_PER_VOLUME * mesh.volume / MAX_DOFS) ** (1.0 / 3.0)
    return float(max(SIZE_PER_THICKNESS * mean_thickness, dof_limited))


def _write_ascii_stl(mesh: trimesh.Trimesh, path: Path) -> None:
    """ASCII STL with "%.17g" coordinates, so netgen reads the vertices exactly."""
    facets = "".join(
        "facet normal 0 0 0\nouter loop\n"
        + "".join("vertex %.17g %.17g %.17g\n" % tuple(v) for v in triangle)
        + "endloop\nendfacet\n"
        for triangle in mesh.triangles
    )
    path.write_text(f"solid surface\n{facets}endsolid surface\n")


def _positively_oriented(points: np.ndarray, tets: np.ndarray) -> np.ndarray:
    """The tetrahedra with two vertices swapped wherever their signed volume is negative."""
    a, b, c, d = (points[tets[:, k]] for k in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets = tets.copy()
    tets[negative, 1], tets[negative, 2] = tets[negative, 2], tets[negative, 1].copy()
    return tets


def _netgen_mesh(mesh: trimesh.Trimesh, size: float):
    import netgen.meshing
    from netgen.stl import STLGeometry

    netgen.meshing.SetMessageImportance(0)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "surface.stl"
        _write_ascii_stl(mesh, path)
        return STLGeometry(str(path)).GenerateMesh(maxh=size)


def tetrahedralise(mesh: trimesh.Trimesh, size: float, name: str = "the surface") -> tuple[np.ndarray, np.ndarray]:
    """Quadrature-ready tetrahedra filling a closed surface.

    Parameters
    ----------
    mesh
        Closed, outward-wound surface, in metres in the body frame O xyz.
    size
        Largest element edge length (m), netgen's ``maxh``.
    name
        What to call the surface in error messages.

    Returns
    -------
    points
        Vertex coordinates (n, 3), m, frame O xyz.
    tets
        Vertex indices (k, 4) of positively oriented tetrahedra.
    """
    if not size > 0:
        raise MasslineError(f"element size {size} m is not positive: give a positive --fe-size")
    try:
        result = _netgen_mesh(mesh, size)
        points = np.array(result.Coordinates(), dtype=float)
        tets = result.Elements3D().NumPy()["nodes"][:, :4].astype(np.int64) - 1
    except Exception as err:  # netgen raises plain Exceptions with C++ messages
        raise MasslineError(
            f"tetrahedral meshing of {name} failed: {str(err).strip() or type(err).__name__}; "
            "check that the surface is closed or try a different --fe-size"
        ) from None
    if len(tets) == 0:
        raise MasslineError(
            f"tetrahedral meshing of {name} gave no tetrahedra; check that the surface is closed "
            "or try a different --fe-size"
        )
    return points, _positively_oriented(points, tets)
