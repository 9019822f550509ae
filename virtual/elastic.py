"""Elastic modes of the free-free solid: quadratic tetrahedra, by scikit-fem.

The body is meshed into tetrahedra (:mod:`.tetmesh`) in its frame O xyz, in
metres; the displacement u (m) is quadratic on each tetrahedron. The stiffness
and consistent mass matrices are

    K = ∫ σ(u) : ε(v) dV,   M = ∫ ρ u · v dV,

and the free-free modes solve K φ = ω² M φ. Six of them are the rigid motions
q = (a_O, α) about O, u(r) = a_O + α × r, which a quadratic field represents
exactly, so Rᵀ M R (R: their nodal fields) is the body's 6×6 rigid-body mass
matrix about O. The elastic modes are returned mass-normalised, φᵀ M φ = 1, and
M-orthogonal to the rigid motions.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg
from scipy.spatial import cKDTree
from skfem import Basis, BilinearForm, ElementTetP2, ElementVector, MeshTet, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from massline.core.errors import MasslineError, param
from massline.core.numbers import number, vector_text
from massline.virtual.tetmesh import default_tetrahedra, tetrahedralise

if TYPE_CHECKING:  # trimesh loads where a surface is read, not for every command that imports this
    import trimesh

N_RIGID = 6
INTORDER = 2  # the basis's quadrature, exact for the stiffness: strains are linear (degree 1 + 1)
MASS_INTORDER = 4  # exact for the mass matrix of quadratic displacements (degree 2 + 2)
SHIFT = 1e-4  # shift-invert at −SHIFT · E/(ρ L²): below the rigid modes, well conditioned
RIGID_LEVEL = 1e-3  # an eigenvalue below RIGID_LEVEL · |shift| is a zero-frequency mode
CANDIDATES = 16  # nearest tetrahedra (by centroid) searched for a point before all of them
FOUND = 1e-12  # a point within this fraction of the element size of a tetrahedron lies in it
OUTSIDE = 0.3  # a point may lie this fraction of the element size outside the meshed solid: netgen's surface cuts
# the corners of a tessellated curve (a 16-section R 10 mm fillet's sphere corner by 2.0 mm, 0.27 h)

MATERIALS = {"steel": (210e9, 0.30, 7850.0), "aluminium": (70e9, 0.33, 2700.0), "titanium": (114e9, 0.34, 4430.0)}
"""Young's modulus (Pa), Poisson's ratio and density (kg/m³) of common metals."""


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material.

    Parameters
    ----------
    youngs
        Young's modulus E, Pa.
    poisson
        Poisson's ratio ν, in (−1, 0.5).
    density
        Density ρ, kg/m³.
    """

    youngs: float
    poisson: float
    density: float

    def __post_init__(self):
        if not self.youngs > 0:
            raise MasslineError(f"Young's modulus {self.youngs} Pa is not physical: give a positive number")
        if not -1.0 < self.poisson < 0.5:
            raise MasslineError(f"Poisson's ratio {self.poisson} is not physical: give a number in (−1, 0.5)")
        if not self.density > 0:
            raise MasslineError(f"density {self.density} kg/m³ is not physical: give a positive number")

    @property
    def wave_speed(self) -> float:
        """√(E/ρ), m/s: the bar wave speed."""
        return float(np.sqrt(self.youngs / self.density))

    @classmethod
    def parse(cls, text: str, density: float) -> "Material":
        """``--material``: a name of ``MATERIALS`` or "E,NU" (Pa, dimensionless), at ``density`` kg/m³."""
        if text in MATERIALS:
            return cls(*MATERIALS[text][:2], density)
        try:
            youngs, poisson = (float(v) for v in text.split(","))
        except ValueError:
            raise MasslineError(
                f"{param('material', repr(text), cli=text)}: give {', '.join(MATERIALS)} or E,NU (e.g. 70e9,0.33)"
            ) from None
        if not (0 < youngs < 1e13 and -1 < poisson < 0.5):
            raise MasslineError(
                f"{param('material', repr(text), cli=text)}: give a finite 0 < E < 1e13 Pa (diamond's is 1.2e12) "
                "and −1 < NU < 0.5"
            )
        return cls(youngs, poisson, density)

    @staticmethod
    def closest(density: float) -> str:
        """The name of the metal of ``MATERIALS`` whose density is closest (in ratio) to ``density``."""
        return min(MATERIALS, key=lambda k: abs(np.log(MATERIALS[k][2] / density)))


def stiffness_form(material: Material) -> BilinearForm:
    """Weak form of K, ∫ σ(u) : ε(v) dV with Lamé's λ, μ from E (Pa) and ν."""
    return linear_elasticity(*lame_parameters(material.youngs, material.poisson))


def mass_form(density: float) -> BilinearForm:
    """Weak form of M, ∫ ρ u · v dV with ρ in kg/m³."""

    @BilinearForm
    def weakform(u, v, w):
        return density * dot(u, v)

    return weakform


def rigid_rows(locations: np.ndarray, components: np.ndarray) -> np.ndarray:
    """Rows (p, 6) of R, ∂u_c(r)/∂(a_O, α) for u = a_O + α × r, at DOFs of locations r (p, 3), m, and components c (p,).

    ∂u_c/∂a_O = e_c and ∂u_c/∂α = r × e_c, since e_c · (α × r) = α · (r × e_c).
    """
    unit = np.eye(3)[components]
    return np.hstack([unit, np.cross(locations, unit)])


@dataclass(frozen=True, eq=False)
class ElasticModes:
    """The lowest elastic free-free modes of a solid, mass-normalised.

    Parameters
    ----------
    omega
        Natural angular frequencies ω (n,), rad/s, ascending.
    shapes
        Nodal mode shapes (n_dofs, n): displacement (m) per unit modal
        coordinate (kg^½·m), frame O xyz; φᵀ M φ = 1.
    basis
        The quadratic-tetrahedron basis the shapes live on.
    element_size
        The element size the solid was meshed with, m.
    """

    omega: np.ndarray
    shapes: np.ndarray
    basis: Basis
    element_size: float

    @property
    def frequencies_hz(self) -> np.ndarray:
        """Natural frequencies ω/2π (n,), Hz."""
        return self.omega / (2 * np.pi)

    @property
    def n_dofs(self) -> int:
        return int(self.basis.N)

    @cached_property
    def _centroids(self) -> cKDTree:
        mesh = self.basis.mesh
        return cKDTree(mesh.p[:, mesh.t].mean(axis=1).T)

    def _clamped(self, x: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Reference coordinates (3, m) of the points of the cells nearest to the points x (3, m) (x itself where
        it lies in its cell, else the nearest point of the cell's four faces), and how far they are from x (m)."""
        mapping, mesh = self.basis.mapping, self.basis.mesh
        local = mapping.invF(x[:, :, None], tind=cells)[:, :, 0]
        out = np.flatnonzero(np.vstack([1 - local.sum(axis=0), local]).min(axis=0) < 0)
        if len(out):
            corners = np.moveaxis(mesh.p[:, mesh.t[:, cells[out]]], 0, -1)  # (4, k, 3)
            faces = np.transpose(corners[[[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]]], (2, 0, 1, 3))  # (k, 4, 3, 3)
            from trimesh.triangles import closest_point

            nearest = closest_point(faces.reshape(-1, 3, 3), np.repeat(x[:, out].T, 4, axis=0))
            nearest = nearest.reshape(len(out), 4, 3)
            closest = np.linalg.norm(nearest - x[:, out].T[:, None], axis=2).argmin(axis=1)
            on_face = nearest[np.arange(len(out)), closest]
            local[:, out] = mapping.invF(on_face.T[:, :, None], tind=cells[out])[:, :, 0]
        barycentric = np.vstack([1 - local.sum(axis=0), local]).clip(min=0)
        local = barycentric[1:] / barycentric.sum(axis=0)
        moved = mapping.F(local[:, :, None], tind=cells)[:, :, 0]
        return local, np.linalg.norm(moved - x, axis=0)

    def _nearest_cell(self, x: np.ndarray) -> int:
        """The tetrahedron nearest the point x (3,), searching all of them."""
        cells = np.arange(self.basis.mesh.t.shape[1])
        return int(cells[np.argmin(self._clamped(np.repeat(x[:, None], len(cells), axis=1), cells)[1])])

    def _cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Nearest cells (p,), clamped reference coordinates (3, p) and distances (p,) m of points (p, 3) in m."""
        k = min(CANDIDATES, self.basis.mesh.t.shape[1])
        candidates = self._centroids.query(points, k)[1].reshape(len(points), k)
        _, distance = self._clamped(np.repeat(points.T, k, axis=1), candidates.ravel())
        cells = candidates[np.arange(len(points)), distance.reshape(-1, k).argmin(axis=1)]
        for i in np.flatnonzero(distance.reshape(-1, k).min(axis=1) > FOUND * self.element_size):
            cells[i] = self._nearest_cell(points[i])
        return (cells, *self._clamped(points.T, cells))

    def nearest(self, points: np.ndarray) -> np.ndarray:
        """The points (p, 3) m of the solid nearest points (p, 3) m: themselves inside it, else on its surface."""
        cells, local, _ = self._cells(np.atleast_2d(points))
        return self.basis.mapping.F(local[:, :, None], tind=cells)[:, :, 0].T

    def _locate(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Cells (p,) and clamped reference coordinates (3, p) of points (p, 3) in m, frame O xyz."""
        cells, local, distance = self._cells(points)
        outside = np.flatnonzero(distance > OUTSIDE * self.element_size)
        if len(outside):
            i = outside[0]
            raise MasslineError(
                f"point {vector_text(points[i])} m lies {number(distance[i], 3)} m outside the solid: "
                "place sensors on or in the body"
            )
        return cells, local

    def shapes_at(self, points: np.ndarray) -> np.ndarray:
        """Mode shapes at points of the solid, on its surface included.

        Parameters
        ----------
        points
            Positions (p, 3), m, frame O xyz.

        Returns
        -------
        np.ndarray
            Displacements (n, p, 3), m per unit modal coordinate, frame O xyz.
        """
        points = np.atleast_2d(np.asarray(points, dtype=float))
        cells, local = self._locate(points)
        values = _basis_values(self.basis, cells, local)
        return np.einsum("kcp,kpm->mpc", values, self.shapes[self.basis.element_dofs[:, cells]])


def _basis_values(basis: Basis, cells: np.ndarray, local: np.ndarray) -> np.ndarray:
    """Values (n_basis, 3, p) of each cell's vector basis functions at reference points local (3, p)."""
    element, mapping = basis.elem, basis.mapping
    return np.array(
        [np.asarray(element.gbasis(mapping, local[:, :, None], k, tind=cells)[0]) for k in range(basis.Nbfun)]
    )[..., 0]


class ElasticBody:
    """A solid of one material, meshed into quadratic tetrahedra.

    Parameters
    ----------
    points
        Vertex coordinates (n, 3), m, frame O xyz.
    tets
        Vertex indices (k, 4) of the tetrahedra.
    material
        Its material.
    element_size
        The size it was meshed with, m; by default its longest edge.
    """

    def __init__(self, points: np.ndarray, tets: np.ndarray, material: Material, element_size: float | None = None):
        self.points = np.ascontiguousarray(points, dtype=float)
        self.tets = np.ascontiguousarray(tets, dtype=np.int64)
        self.material = material
        self._element_size = element_size

    @classmethod
    def from_mesh(
        cls,
        mesh: trimesh.Trimesh,
        material: Material,
        size: float | None = None,
        name: str = "the surface",
        progress=None,
    ) -> "ElasticBody":
        """Mesh a closed surface (m, frame O xyz) with element size ``size`` (m; default :func:`.default_tetrahedra`).

        ``progress(stage)``, when given, is called with "meshing" before the work starts.
        """
        if progress is not None:
            progress("meshing")
        if size is None:
            size, points, tets = default_tetrahedra(mesh, name)
            return cls(points, tets, material, size)
        return cls(*tetrahedralise(mesh, float(size), name), material, float(size))

    @cached_property
    def element_size(self) -> float:
        """The meshing size, m; the longest tetrahedron edge when none was given."""
        if self._element_size is not None:
            return float(self._element_size)
        edges = self.points[self.tets[:, [0, 0, 0, 1, 1, 2]]] - self.points[self.tets[:, [1, 2, 3, 2, 3, 3]]]
        return float(np.linalg.norm(edges, axis=-1).max())

    @cached_property
    def basis(self) -> Basis:
        """Quadratic vector basis on the tetrahedra; its quadrature integrates degree 2 exactly."""
        mesh = MeshTet(np.ascontiguousarray(self.points.T), np.ascontiguousarray(self.tets.T))
        return Basis(mesh, ElementVector(ElementTetP2()), intorder=INTORDER)

    @property
    def n_dofs(self) -> int:
        return int(self.basis.N)

    @cached_property
    def stiffness(self) -> scipy.sparse.csr_matrix:
        """K (n_dofs, n_dofs), N/m."""
        return asm(stiffness_form(self.material), self.basis)

    @cached_property
    def mass(self) -> scipy.sparse.csr_matrix:
        """M (n_dofs, n_dofs), kg, integrated exactly (on a basis dropped afterwards: it holds ~300 MB at 50k DOF)."""
        return asm(mass_form(self.material.density), Basis(self.basis.mesh, self.basis.elem, intorder=MASS_INTORDER))

    @cached_property
    def rigid_fields(self) -> np.ndarray:
        """R (n_dofs, 6): the nodal fields of the unit rigid motions (a_O, α), u = a_O + α × r."""
        components = np.empty(self.n_dofs, dtype=int)
        for c in range(3):
            components[self.basis.nodal_dofs[c]] = c
            components[self.basis.edge_dofs[c]] = c
        return rigid_rows(self.basis.doflocs.T, components)

    @cached_property
    def rigid_block(self) -> np.ndarray:
        """Rᵀ M R (6, 6): the rigid-body mass matrix about O, [[m I, −m[c]×], [m[c]×, J_O]] in SI."""
        return self.rigid_fields.T @ (self.mass @ self.rigid_fields)

    @property
    def shift(self) -> float:
        """The shift of shift-invert, (rad/s)²: −SHIFT · E/(ρ L²) with L the largest extent (m)."""
        extent = float(np.ptp(self.points, axis=0).max())
        return -SHIFT * (self.material.wave_speed / extent) ** 2

    def _solver(self) -> scipy.sparse.linalg.LinearOperator:
        """(K − σM)⁻¹ by a sparse LU without pivoting (K − σM is positive definite), σ the shift."""
        lu = scipy.sparse.linalg.splu(
            (self.stiffness - self.shift * self.mass).tocsc(),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
        return scipy.sparse.linalg.LinearOperator((self.n_dofs,) * 2, matvec=lu.solve, dtype=float)

    def _deflated(self, vectors: np.ndarray) -> np.ndarray:
        """The vectors (n_dofs, k) with their rigid part removed: M-orthogonal to R."""
        R = self.rigid_fields
        return vectors - R @ np.linalg.solve(self.rigid_block, R.T @ (self.mass @ vectors))

    def modes(self, n: int, progress=None) -> ElasticModes:
        """The n lowest elastic free-free modes, mass-normalised and M-orthogonal to the rigid motions.

        ``progress(stage)``, when given, is called as each stage starts: "assembling stiffness",
        "assembling mass", "solving for modes".
        """
        if not 1 <= n <= self.n_dofs - N_RIGID - 1:
            raise MasslineError(f"cannot compute {n} elastic modes of a model with {self.n_dofs} DOF")
        for stage, step in (
            ("assembling stiffness", lambda: self.stiffness),
            ("assembling mass", lambda: self.mass),
            ("solving for modes", lambda: None),
        ):
            if progress is not None:
                progress(stage)
            step()
        K, M, shift = self.stiffness, self.mass, self.shift
        values, vectors = scipy.sparse.linalg.eigsh(K, n + N_RIGID, M, sigma=shift, OPinv=self._solver())
        order = np.argsort(values)
        if values[order[N_RIGID]] < RIGID_LEVEL * abs(shift):
            raise MasslineError(
                "the solid has more than six zero-frequency modes: its tetrahedra form separate pieces; "
                "mesh a single connected body"
            )
        subspace = self._deflated(vectors[:, order[N_RIGID:]])
        omega_squared, coefficients = scipy.linalg.eigh(subspace.T @ (K @ subspace), subspace.T @ (M @ subspace))
        return ElasticModes(np.sqrt(omega_squared), subspace @ coefficients, self.basis, self.element_size)
