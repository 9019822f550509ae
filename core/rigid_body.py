"""Rigid-body inertia: the 10 parameters, the mass matrix about O, frame changes.

Conventions (DESIGN.md): one frame O xyz, SI units. The inertia tensor has the
tensor sign, J = ∫(|r|² I − r rᵀ) dm, so its off-diagonal entries are minus the
products of inertia. The 10 parameters are

    θ = (m, m c_x, m c_y, m c_z, J_xx, J_yy, J_zz, J_xy, J_yz, J_xz)

with J about O, and the mass matrix about O is linear in them:

    M_O = [[m I, −m [c]×], [m [c]×, J_O]],   J_O = J_G − m [c]× [c]×.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import skew

PARAMETER_NAMES = ("m", "mc_x", "mc_y", "mc_z", "J_xx", "J_yy", "J_zz", "J_xy", "J_yz", "J_xz")
SIX_INDEX = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))  # (xx, yy, zz, xy, yz, xz)


def tensor_from_six(j: np.ndarray) -> np.ndarray:
    """Symmetric 3×3 tensor from its six entries (xx, yy, zz, xy, yz, xz)."""
    xx, yy, zz, xy, yz, xz = j
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def six_from_tensor(J: np.ndarray) -> np.ndarray:
    """The six entries (xx, yy, zz, xy, yz, xz) of a symmetric 3×3 tensor."""
    return np.array([J[i, k] for i, k in SIX_INDEX])


def symmetric_product_matrix(v: np.ndarray) -> np.ndarray:
    """The 3×6 matrix R(v) with ``tensor_from_six(j) @ v == R(v) @ j``.

    It turns J α (method 3, eq. 9) or A v (method 1, eq. 8) into a product with
    the unknown six entries.
    """
    x, y, z = v
    return np.array(
        [
            [x, 0.0, 0.0, y, 0.0, z],
            [0.0, y, 0.0, x, z, 0.0],
            [0.0, 0.0, z, 0.0, y, x],
        ]
    )


def steiner(mass: float, offset: np.ndarray) -> np.ndarray:
    """Parallel-axis term −m [c]×[c]× = m (|c|² I − c cᵀ), kg·m²."""
    c = np.asarray(offset, dtype=float)
    return mass * (c @ c * np.eye(3) - np.outer(c, c))


def assembled_mass_matrix(theta: np.ndarray) -> np.ndarray:
    """6×6 mass matrix about O from the 10 parameters θ, assembled block by block: [[m I, −[mc]×], [[mc]×, J_O]]."""
    m, mc, j = theta[0], np.asarray(theta[1:4]), theta[4:]
    return np.block([[m * np.eye(3), -skew(mc)], [skew(mc), tensor_from_six(j)]])


BASIS = np.array([assembled_mass_matrix(e) for e in np.eye(10)])  # B_k, entries 0 and ±1
BASIS.flags.writeable = False


def mass_matrix(theta: np.ndarray) -> np.ndarray:
    """6×6 mass matrix about O from the 10 parameters θ: Σ θ_k B_k (exactly the assembled one: the B_k hold 0 and
    ±1; a contraction, without the assembly's per-call cost in the diagnosis's fits)."""
    return np.tensordot(np.asarray(theta, dtype=float), BASIS, axes=1)


def mass_matrix_basis() -> np.ndarray:
    """∂M_O/∂θ_k for k = 0..9, shape (10, 6, 6): M_O = Σ θ_k B_k."""
    return BASIS.copy()


def theta_from_mass_matrix(M: np.ndarray) -> np.ndarray:
    """The 10 parameters read off a 6×6 mass matrix about O."""
    mc = np.array([M[5, 1], M[3, 2], M[4, 0]])
    return np.concatenate([[M[0, 0]], mc, six_from_tensor(M[3:, 3:])])


def mass_matrix_regressor(q: np.ndarray) -> np.ndarray:
    """The 6×10 matrix Y(q) with ``mass_matrix(θ) @ q == Y(q) @ θ``.

    For q = (a_O, α): the force rows are m a_O + α × (m c), the moment rows are
    −a_O × (m c) + J_O α (method 3, eq. 9, written about O).
    """
    a, alpha = q[:3], q[3:]
    top = np.hstack([a[:, None], skew(alpha), np.zeros((3, 6))])
    bottom = np.hstack([np.zeros((3, 1)), -skew(a), symmetric_product_matrix(alpha)])
    return np.vstack([top, bottom])


def principal(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending, kg·m²) and axes (columns, right-handed).

    Each axis but the last is signed so that its largest component is
    positive; the last is signed to make the basis right-handed. The choice is arbitrary but
    deterministic, so that two tools report the same axes.
    """
    moments, axes = np.linalg.eigh(inertia)
    n = len(moments)
    for k in range(n - 1):
        if axes[np.argmax(np.abs(axes[:, k])), k] < 0:
            axes[:, k] *= -1
    axes[:, -1] *= np.sign(np.linalg.det(axes))
    return moments, axes


def physical_mass(m: float) -> float:
    """``m`` (kg) when a body can have it; MasslineError otherwise (an estimate run off to m ≤ 0)."""
    if not m > 0:
        raise MasslineError(f"a mass of {m:.4g} kg is not physical: the data or the layout are wrong")
    return m


@dataclass(frozen=True, eq=False)
class RigidBody:
    """Mass (kg), centre of gravity (m) and inertia about the CoG (kg·m²), frame O xyz."""

    mass: float
    cog: np.ndarray
    inertia_cog: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "mass", float(self.mass))
        object.__setattr__(self, "cog", np.asarray(self.cog, dtype=float).reshape(3))
        J = np.asarray(self.inertia_cog, dtype=float).reshape(3, 3)
        object.__setattr__(self, "inertia_cog", 0.5 * (J + J.T))

    @classmethod
    def from_theta(cls, theta: np.ndarray) -> "RigidBody":
        """The body of the 10 parameters θ (J about O)."""
        m = physical_mass(theta[0])
        cog = np.asarray(theta[1:4]) / m
        return cls(m, cog, tensor_from_six(theta[4:]) - steiner(m, cog))

    @cached_property
    def inertia_origin(self) -> np.ndarray:
        """J_O = J_G − m [c]×[c]×, kg·m²."""
        return self.inertia_cog + steiner(self.mass, self.cog)

    @cached_property
    def theta(self) -> np.ndarray:
        return np.concatenate([[self.mass], self.mass * self.cog, six_from_tensor(self.inertia_origin)])

    @cached_property
    def mass_matrix(self) -> np.ndarray:
        return mass_matrix(self.theta)

    @cached_property
    def principal_moments(self) -> np.ndarray:
        return principal(self.inertia_cog)[0]

    @cached_property
    def principal_axes(self) -> np.ndarray:
        return principal(self.inertia_cog)[1]

    @cached_property
    def radius_of_gyration(self) -> float:
        """√(tr J_G / 2m), m: the length that makes CoG errors comparable (nan for no body: tr J_G / m ≤ 0, which a
        gross fault's masslines can give; its callers refuse it)."""
        with np.errstate(invalid="ignore"):
            return float(np.sqrt(np.trace(self.inertia_cog) / (2 * self.mass)))

    def transformed(self, rotation: np.ndarray, translation: np.ndarray) -> "RigidBody":
        """The same body seen in a frame where x' = R x + t."""
        R = np.asarray(rotation, dtype=float)
        return RigidBody(self.mass, R @ self.cog + translation, R @ self.inertia_cog @ R.T)

    def scaled(self, length: float = 1.0, mass: float = 1.0) -> "RigidBody":
        """The same body in other units: lengths × ``length``, masses × ``mass``."""
        return RigidBody(self.mass * mass, self.cog * length, self.inertia_cog * mass * length**2)

    def as_dict(self) -> dict:
        """DESIGN.md's identify keys (values only)."""
        return {
            "mass": self.mass,
            "cog": self.cog.tolist(),
            "inertia_cog": self.inertia_cog.tolist(),
            "principal_moments": self.principal_moments.tolist(),
            "principal_axes": self.principal_axes.tolist(),
        }
