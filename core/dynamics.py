"""Dynamics: mass, CoG and inertia from rigid accelerations (paper §2.2).

Input is the kinematic solution Q (6 × K) for K exciters, each a unit force
along line j (point r_j, direction d_j, moment m_j = r_j × d_j). Newton–Euler
(eqs. 3–4) for a unit force:

    d_j = m a_G,          (r_j − c) × d_j = J_G α_j,      a_G = a_O + α × c.

The three methods differ in which of these they make linear.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.degeneracy import exciter_hint
from massline.core.errors import SingularLayoutError
from massline.core.kinematics import RigidAccelerations, default_pairs, difference_rows
from massline.core.linear_system import solve
from massline.core.lines import skew
from massline.core.masslines import Masslines
from massline.core.rigid_body import RigidBody, symmetric_product_matrix, tensor_from_six


@dataclass(frozen=True, eq=False)
class MethodResult:
    """What one of the paper's methods identified: properties in the test frame, with the conditioning met.

    ``mass`` is None when the method cannot give it (dynamics method 1);
    ``condition`` maps each solved system to its 2-norm condition number.
    """

    mass: float | None
    cog: np.ndarray
    inertia_cog: np.ndarray
    condition: dict = field(default_factory=dict)
    method: str = ""

    @property
    def body(self) -> RigidBody:
        if self.mass is None:
            raise SingularLayoutError(f"{self.method} does not identify the mass; use method 2 or 3")
        return RigidBody(self.mass, self.cog, self.inertia_cog)


def _stack_rows(blocks) -> np.ndarray:
    return np.vstack(list(blocks))


def inverse_inertia_from_pairs(data: Masslines, acc: RigidAccelerations, pairs) -> tuple[np.ndarray, float]:
    """A = J_G⁻¹ from the 9 × 6 difference system under eq. (8).

    Two parallel exciters j, k give α_j − α_k = A ((r_j − r_k) × d), linear in
    the six entries of A (the CoG cancels).
    """
    alpha = acc.alpha.T  # one row per exciter
    moments, rhs = difference_rows(data.exciters, alpha, pairs, "exciters")
    A_rows = _stack_rows(symmetric_product_matrix(v) for v in moments)
    six, kappa = solve(
        A_rows,
        rhs.reshape(-1),
        "dynamics method 1, difference system under eq. (8)",
        lambda: exciter_hint(data.exciters),
    )
    return tensor_from_six(six), kappa


def method1(data: Masslines, acc: RigidAccelerations, pairs=None) -> MethodResult:
    """Method 1, eq. (8): A = J_G⁻¹ by differences, then the CoG; no mass.

    With A known, eq. (8) for every exciter, J_G α_j = m_j − c × d_j, is linear
    in c: −[d_j]× c = m_j − J_G α_j (the paper's 9 × 3 system). Six exciters
    (two per direction) × six sensors: 36 measurements.
    """
    pairs = default_pairs(data.exciters) if pairs is None else pairs
    A, kappa_A = inverse_inertia_from_pairs(data, acc, pairs)
    J = np.linalg.inv(A)
    d, m = data.exciters.directions, data.exciters.moments
    rows = _stack_rows(-skew(dj) for dj in d)
    rhs = (m - acc.alpha.T @ J).reshape(-1)
    cog, kappa_c = solve(rows, rhs, "dynamics method 1, CoG system", lambda: exciter_hint(data.exciters))
    condition = {**acc.condition, "inverse_inertia": kappa_A, "cog": kappa_c}
    return MethodResult(None, cog, J, condition, f"kinematics {acc.method} + dynamics method1")


def inertia_from_inverse(data: Masslines, acc: RigidAccelerations, cog: np.ndarray) -> tuple[np.ndarray, float]:
    """J_G from eq. (8) with the CoG known: α_j = A ((r_j − c) × d_j), linear in A."""
    v = data.exciters.moments - np.cross(cog, data.exciters.directions)
    rows = _stack_rows(symmetric_product_matrix(vj) for vj in v)
    six, kappa = solve(
        rows, acc.alpha.T.reshape(-1), "inverse inertia, eq. (8) with known CoG", lambda: exciter_hint(data.exciters)
    )
    return np.linalg.inv(tensor_from_six(six)), kappa


def method2(data: Masslines, acc: RigidAccelerations) -> MethodResult:
    """Method 2: 1/M and the CoG from responses along the force, then eq. (8).

    From eq. (1), a sensor i parallel to exciter j reads
    H_ij − (r_i × s_i) · α_j = (s_i · d_j)/M − (s_i × α_j) · c,
    one row of the 4-unknown system per such pair (four excitations, 24
    transductions in the paper). The inverse inertia then follows from
    eq. (8) with the CoG known. (The paper prints the α columns with the
    opposite sign; this is eq. (1) as written.)
    """
    s, r_x_s = data.sensors.directions, data.sensors.moments
    rows, rhs = [], []
    for j, dj in enumerate(data.exciters.directions):
        alpha = acc.alpha[:, j]
        for i in np.flatnonzero(np.linalg.norm(np.cross(s, dj), axis=1) < 1e-9):
            rows.append(np.concatenate([[s[i] @ dj], -np.cross(s[i], alpha)]))
            rhs.append(data.values[i, j] - r_x_s[i] @ alpha)
    unknowns, kappa = solve(
        np.array(rows).reshape(-1, 4),
        np.array(rhs),
        "dynamics method 2 (mass and CoG)",
        "it needs four excitations, each with a sensor along the force; " + exciter_hint(data.exciters),
    )
    mass, cog = 1.0 / unknowns[0], unknowns[1:]
    J, kappa_J = inertia_from_inverse(data, acc, cog)
    condition = {**acc.condition, "mass_cog": kappa, "inverse_inertia": kappa_J}
    return MethodResult(mass, cog, J, condition, f"kinematics {acc.method} + dynamics method2")


def method3(data: Masslines, acc: RigidAccelerations) -> MethodResult:
    """Method 3 (the paper's choice, eq. 9): force rows, then moment rows.

    Force rows, per exciter: d_j = a_O,j m + [α_j]× (m c), linear in (m, m c).
    Moment rows about G: (r_j − c) × d_j = J_G α_j, linear in the six entries
    of J_G once c is known. Three exciters × six sensors = 18 measurements
    make the determined system with eq. (6).
    """
    d = data.exciters.directions
    force_rows = _stack_rows(np.hstack([acc.a_origin[:, [j]], skew(acc.alpha[:, j])]) for j in range(len(d)))
    m_mc, kappa_f = solve(
        force_rows, d.reshape(-1), "dynamics method 3, force equations", lambda: exciter_hint(data.exciters)
    )
    mass, cog = m_mc[0], m_mc[1:] / m_mc[0]
    moment_rows = _stack_rows(symmetric_product_matrix(acc.alpha[:, j]) for j in range(len(d)))
    rhs = (data.exciters.moments - np.cross(cog, d)).reshape(-1)
    six, kappa_m = solve(moment_rows, rhs, "dynamics method 3, moment equations", lambda: exciter_hint(data.exciters))
    condition = {**acc.condition, "translation": kappa_f, "rotation": kappa_m}
    return MethodResult(mass, cog, tensor_from_six(six), condition, f"kinematics {acc.method} + dynamics method3")
