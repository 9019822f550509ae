"""The rigid-body model a layout is judged on: 3-D (10 parameters) or plate (6).

Both are the same algebra in q dimensions with p parameters:

    H_ij = ℓ_iᵀ M(θ)⁻¹ w_j,     M(θ) = Σ_k θ_k B_k     (q × q),

with ℓ the sensor line's coordinates and w the exciter's. In 3-D, q = 6 and
ℓ = (d, r × d) (DESIGN.md); for the plate (§2.3), q = 3 on (a_z, α_x, α_y) and
ℓ = (d_z, y d_z, −x d_z). The parameters are non-dimensionalised by the nominal
mass m₀ and radius of gyration L (θ̃ = θ / (m₀, m₀L, m₀L²)), which shifts log det
by a constant only and keeps the numerics well scaled.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property

import numpy as np

from massline.core.lines import Lines
from massline.core.plate import PLATE_PARAMETER_NAMES, plate_coordinates, plate_mass_matrix, plate_theta
from massline.core.rigid_body import (
    PARAMETER_NAMES,
    RigidBody,
    mass_matrix,
    mass_matrix_basis,
    physical_mass,
    steiner,
    tensor_from_six,
)


@cache
def unit_basis(planar: bool) -> np.ndarray:
    """∂M/∂θ_k (p, q, q) in SI parameters: M(θ) = Σ θ_k B_k is linear, so one basis serves every model."""
    basis = np.array([plate_mass_matrix(e) for e in np.eye(6)]) if planar else mass_matrix_basis()
    basis.flags.writeable = False
    return basis


@dataclass(frozen=True, eq=False)
class RigidModel:
    """A parameterised mass matrix at the nominal body, for sensitivities."""

    nominal: RigidBody
    planar: bool = False

    @property
    def names(self) -> tuple:
        return PLATE_PARAMETER_NAMES if self.planar else PARAMETER_NAMES

    @property
    def p(self) -> int:
        return len(self.names)

    @cached_property
    def scale(self) -> np.ndarray:
        """(m₀, m₀L, m₀L²) per parameter: θ = scale · θ̃."""
        m, L = self.nominal.mass, self.nominal.radius_of_gyration
        powers = [0, 1, 1, 2, 2, 2] if self.planar else [0, 1, 1, 1, 2, 2, 2, 2, 2, 2]
        return m * L ** np.array(powers, dtype=float)

    @cached_property
    def theta(self) -> np.ndarray:
        """Nominal parameters in SI units."""
        b = self.nominal
        return plate_theta(b.mass, b.cog, b.inertia_cog) if self.planar else b.theta

    def mass_matrix(self, theta: np.ndarray) -> np.ndarray:
        return plate_mass_matrix(theta) if self.planar else mass_matrix(theta)

    @cached_property
    def basis(self) -> np.ndarray:
        """∂M/∂θ̃_k, shape (p, q, q), in the scaled parameters."""
        return unit_basis(self.planar) * self.scale[:, None, None]

    @cached_property
    def mass_matrix_inverse(self) -> np.ndarray:
        return np.linalg.inv(self.mass_matrix(self.theta))

    def coordinates(self, lines: Lines) -> np.ndarray:
        """Line coordinates ℓ (n, q) in this model."""
        return plate_coordinates(lines) if self.planar else lines.coordinates

    def body(self, theta: np.ndarray) -> RigidBody:
        """The body of SI parameters θ (plate: CoG in z = 0, J_zz etc. kept nominal)."""
        if not self.planar:
            return RigidBody.from_theta(theta)
        m, mcx, mcy, jxx, jyy, jxy = theta
        m = physical_mass(m)
        cog = np.array([mcx / m, mcy / m, 0.0])
        J_O = tensor_from_six([jxx, jyy, self.nominal.inertia_origin[2, 2], jxy, 0.0, 0.0])
        return RigidBody(m, cog, J_O - steiner(m, cog))
