"""Fisher information of a sensor × exciter layout (DESIGN.md, "Information").

For sensor i and exciter j the massline is H_ij = ℓ_iᵀ M⁻¹ w_j and its
sensitivity to the scaled parameters is

    g_ij,k = ∂H_ij/∂θ̃_k = −ℓ_iᵀ M⁻¹ B_k M⁻¹ w_j = −u_iᵀ Y(v_j)_k,

with u_i = M⁻¹ ℓ_i, v_j = M⁻¹ w_j and Y(v) = [B_1 v … B_p v]. Each B_k is
symmetric, so g_ij and H_ij are symmetric in the two lines: a sensor and an
exciter on the same line have the same sensitivities. With noise σ_ij
on each massline the information is F = Σ_ij g_ij g_ijᵀ / σ_ij²: linear in the
chosen sensors for fixed exciters and vice versa. It is the information of the
whole chain (kinematic and dynamic steps together), which is what an efficient
estimator attains.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.model import RigidModel


@dataclass(frozen=True)
class NoiseModel:
    """σ_ij = √((relative · H_ij)² + (floor / m₀)²), in (m/s²)/N.

    ``relative``: fraction of each massline (calibration, band-fit scatter);
    ``floor``: a fraction of 1/m₀, the driving-point massline of a point mass.
    It stands for what small cross-masslines cannot go below: an accelerometer's
    transverse sensitivity (3–5 %, paper §3) times the acceleration across its
    axis, of order 1/m₀ per newton. Defaults: 1 % and 2 %.
    """

    relative: float = 0.01
    floor: float = 0.02

    def sigma(self, H: np.ndarray, mass: float) -> np.ndarray:
        return np.sqrt((self.relative * H) ** 2 + (self.floor / mass) ** 2)


def driven_inverses(model: RigidModel, riding: np.ndarray) -> np.ndarray:
    """M_j⁻¹ (n_e, q, q) of the body each exciter drives, M_j = M(θ + θ_j): the model's body with the mass riding
    at exciter j's point (SI parameters ``riding`` (n_e, p), e.g. a force gauge's structure side; eq. 14)."""
    return np.linalg.inv(np.array([model.mass_matrix(model.theta + theta) for theta in riding]))


def driven(model: RigidModel, exciter_coords: np.ndarray, riding: np.ndarray | None = None) -> np.ndarray:
    """v_j = M_j⁻¹ ℓ_j (n_e, q): the rigid acceleration per newton of each exciter, on the body it drives
    (:func:`driven_inverses`; ``riding`` None: the model's body for every exciter)."""
    if riding is None:
        return exciter_coords @ model.mass_matrix_inverse
    return np.einsum("jab,jb->ja", driven_inverses(model, riding), exciter_coords)


def sensitivities(model: RigidModel, sensor_coords: np.ndarray, exciter_coords: np.ndarray, riding=None):
    """g_ij (..., n_sensors, n_exciters, p) and the masslines H_ij (..., n_sensors, n_exciters) at the model, for
    line coordinates (..., n, q): one layout, or a stack of them (one layout only with ``riding``).

    Summed as g_ij,k = −Σ_a u_ia Y(v_j)_ak by einsum: fast when the exciters are few (pass the many
    lines first, by the symmetry above), and single-threaded, which a tall product with a
    six-long inner dimension gains nothing from. With ``riding`` (SI parameters (n_e, p) of a mass riding at
    each exciter), column j is the body M_j = M(θ + θ_j) exciter j drives: H_ij = ℓ_iᵀ M_j⁻¹ ℓ_j and
    g_ij,k = −ℓ_iᵀ M_j⁻¹ B_k M_j⁻¹ ℓ_j (∂M_j/∂θ̃_k = B_k, as for the bare body).
    """
    if riding is not None:
        inverses = driven_inverses(model, riding)
        U = np.einsum("ia,jab->ijb", sensor_coords, inverses)  # u_ij = M_j⁻¹ ℓ_i
        V = np.einsum("jab,jb->ja", inverses, exciter_coords)
        G = -np.einsum("ija,kab,jb->ijk", U, model.basis, V)
        return G, np.einsum("ija,ja->ij", U, exciter_coords)
    Minv = model.mass_matrix_inverse
    U = sensor_coords @ Minv  # u_i (M symmetric)
    V = exciter_coords @ Minv  # v_j
    Y = np.einsum("kab,...jb->...ajk", model.basis, V)  # Y(v_j) side by side: (..., q, n_e, p)
    return -np.einsum("...ia,...ajk->...ijk", U, Y), np.einsum("...ia,...ja->...ij", U, exciter_coords)


def weighted_sensitivities(
    model: RigidModel, sensor_coords: np.ndarray, exciter_coords: np.ndarray, noise: NoiseModel
) -> np.ndarray:
    """g_ij / σ_ij for every pair, shape (..., n_sensors, n_exciters, p)."""
    G, H = sensitivities(model, sensor_coords, exciter_coords)
    return G / noise.sigma(H, model.nominal.mass)[..., None]


def fisher(model: RigidModel, sensor_coords: np.ndarray, exciter_coords: np.ndarray, noise: NoiseModel) -> np.ndarray:
    """F = Σ_ij g_ij g_ijᵀ / σ_ij², in the scaled parameters (p × p)."""
    A = weighted_sensitivities(model, sensor_coords, exciter_coords, noise).reshape(-1, model.p)
    return A.T @ A


def log_det(F: np.ndarray) -> float:
    """log det F, −inf when F is singular."""
    sign, value = np.linalg.slogdet(F)
    return float(value) if sign > 0 else -np.inf
