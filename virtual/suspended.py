"""The body as it hangs in the test: rigid motion, elastic modes, suspension and added masses.

A reduced (Ritz) model in the coordinates x = (q, p): the six rigid-body
coordinates q = (u_O, φ) at O and the modal coordinates p of the free-free
elastic modes (mass-normalised). A point r of the body moves by

    u(r) = Ψ(r) x,    Ψ(r) = [P(r), Φ(r)],   P(r) = [I, −[r]×]

and the model's matrices are

    M = blockdiag(M_O, I) + Σ_s m_s Ψ(r_s)ᵀ Ψ(r_s)          (added sensor masses)
    K = blockdiag(K_g, diag ω_r²) + Σ_a Ψ_aᵀ K_a Ψ_a           (gravity, elastic modes, support springs)
    D = η_s Σ_a Ψ_aᵀ K_a Ψ_a + blockdiag(0, diag η_r ω_r²)      (hysteretic damping)

A support acts on the elastic modes too: Ψ_a = [P(a), Φ(a')] takes the rigid
motion at the support point a (a bridle apex may lie off the solid) and the
elastic motion at a', the point of the solid nearest to it, where the cord or
the pad passes its force in. Through the body's static flexibility this adds
−(A_ia K_a R_aj + R_ia K_a A_aj) to every massline (A the rigid accelerance,
R = Φ Λ⁻¹ Φᵀ the elastic modes' flexibility): of the order of (f_support/f₁)²,
a per cent for a cord whose bounce is a tenth of the first elastic mode.

so that the accelerance between a sensor (point r_i, reading vector n_i) and a
force (point r_j, unit direction d_j) is, as the paper's eq. (14) writes it,

    H_ij(ω) = −ω² n_iᵀ Ψ(r_i) [K + iD − ω² M]⁻¹ Ψ(r_j)ᵀ d_j.

With no suspension, no added mass and no elastic modes it is exactly the
massline S M_O⁻¹ Wᵀ at every frequency.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
from scipy.linalg import eigh

from massline.core.rigid_body import RigidBody, theta_from_mass_matrix
from massline.virtual.suspension import Suspension, point_map

CHUNK = 256  # frequencies solved at once, to bound memory


@dataclass(frozen=True, eq=False)
class SuspendedBody:
    """The rigid body, its elastic modes and its support, with sensor masses added.

    Attributes
    ----------
    body : RigidBody
        Nominal rigid-body properties (mass matrix about O).
    modes : object with ``omega`` (n,) rad/s, ``shapes_at(points) -> (n, p, 3)`` and ``nearest(points)``, or None
        Free-free elastic modes, mass-normalised; None for a rigid body.
    suspension : Suspension
        The support; ``Suspension()`` is the free body.
    masses : (k,) array
        Point masses added to the body (sensors, cables), kg.
    mass_points : (k, 3) array
        Where they sit, m.
    modal_loss : float
        Loss factor η_r of every elastic mode (2ζ).
    """

    body: RigidBody
    modes: object | None = None
    suspension: Suspension = field(default_factory=Suspension)
    masses: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mass_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    modal_loss: float = 0.002

    @property
    def n_elastic(self) -> int:
        return 0 if self.modes is None else len(self.modes.omega)

    def shapes(self, points: np.ndarray) -> np.ndarray:
        """Ψ(r) for each point: (p, 3, 6 + n), displacement per model coordinate."""
        points = np.atleast_2d(points)
        rigid = np.stack([point_map(r) for r in points])
        if self.modes is None:
            return rigid
        elastic = np.transpose(self.modes.shapes_at(points), (1, 2, 0))
        return np.concatenate([rigid, elastic], axis=2)

    @cached_property
    def loaded(self) -> RigidBody:
        """The rigid body with the added masses: what the suspension carries and the test identifies."""
        return RigidBody.from_theta(theta_from_mass_matrix(self.mass_matrix[:6, :6]))

    @cached_property
    def _springs(self) -> np.ndarray:
        n = 6 + self.n_elastic
        K = np.zeros((n, n))
        for point, k in self.suspension.point_springs(self.loaded):
            psi = self.support_shape(point)
            K += psi.T @ k @ psi
        return K

    def support_shape(self, point: np.ndarray) -> np.ndarray:
        """Ψ_a (3, 6 + n) at a support point (m): its rigid motion, and the elastic motion of the solid's point
        nearest to it (the point itself where it lies on or in the solid)."""
        rigid = point_map(point)
        if self.modes is None:
            return rigid
        solid = self.modes.nearest(point[None])
        return np.hstack([rigid, self.modes.shapes_at(solid)[:, 0, :].T])

    @cached_property
    def mass_matrix(self) -> np.ndarray:
        n = 6 + self.n_elastic
        M = np.zeros((n, n))
        M[:6, :6] = self.body.mass_matrix
        M[6:, 6:] = np.eye(self.n_elastic)
        if len(self.masses):
            psi = self.shapes(self.mass_points)
            M += np.einsum("k,kai,kaj->ij", self.masses, psi, psi)
        return M

    @cached_property
    def stiffness_matrix(self) -> np.ndarray:
        K = self._springs.copy()
        K[3:6, 3:6] += self.suspension.geometric_stiffness(self.loaded)
        if self.n_elastic:
            K[6:, 6:] += np.diag(self.modes.omega**2)
        return 0.5 * (K + K.T)

    @cached_property
    def damping_matrix(self) -> np.ndarray:
        D = self.suspension.loss_factor * self._springs
        if self.n_elastic:
            D[6:, 6:] += np.diag(self.modal_loss * self.modes.omega**2)
        return D

    def carrying(self, mass: float, point: np.ndarray) -> "SuspendedBody":
        """This body with ``mass`` kg riding at ``point`` (m), on this body's support stiffness and damping: a
        force gauge of a few per cent of the body tilts it on its cords by a fraction of a degree, which changes
        the support's stiffness far less than the gauge changes the masslines."""
        loaded = replace(self, masses=np.append(self.masses, mass), mass_points=np.vstack([self.mass_points, point]))
        loaded.__dict__.update(stiffness_matrix=self.stiffness_matrix, damping_matrix=self.damping_matrix)
        return loaded

    @cached_property
    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural frequencies of the suspended body, Hz, ascending (6 + n)."""
        eigenvalues = eigh(self.stiffness_matrix, self.mass_matrix, eigvals_only=True)
        return np.sqrt(np.clip(eigenvalues, 0.0, None)) / (2 * np.pi)

    @property
    def suspension_frequencies(self) -> np.ndarray:
        """The six lowest natural frequencies (the suspension modes), Hz."""
        return self.natural_frequencies[:6]

    @property
    def first_elastic_frequency(self) -> float:
        """Lowest elastic natural frequency of the suspended body, Hz (inf for a rigid one)."""
        return float(self.natural_frequencies[6]) if self.n_elastic else np.inf

    def accelerance(
        self,
        frequencies: np.ndarray,
        sensor_points: np.ndarray,
        sensor_vectors: np.ndarray,
        exciter_points: np.ndarray,
        exciter_vectors: np.ndarray,
    ) -> np.ndarray:
        """H_ij(f), (m/s²)/N, shape (n_s, n_e, n_f): eq. (14) of the reduced model.

        ``sensor_vectors`` are what each accelerometer reads per m/s² of its
        point's acceleration (its axis, scaled by its gain, with any
        transverse sensitivity); ``exciter_vectors`` the force per newton of
        the recorded force signal.
        """
        read = np.einsum("sa,sad->sd", sensor_vectors, self.shapes(sensor_points))
        push = np.einsum("ea,ead->ed", exciter_vectors, self.shapes(exciter_points))
        omega = 2 * np.pi * np.asarray(frequencies, dtype=float)
        H = np.empty((len(read), len(push), len(omega)), dtype=complex)
        K = self.stiffness_matrix + 1j * self.damping_matrix
        for start in range(0, len(omega), CHUNK):
            w = omega[start : start + CHUNK]
            Z = K[None] - (w**2)[:, None, None] * self.mass_matrix[None]
            X = np.linalg.solve(Z, np.broadcast_to(push.T, (len(w),) + push.T.shape))
            H[:, :, start : start + CHUNK] = np.einsum("sd,fde->sef", read, X) * -(w**2)
        return H
