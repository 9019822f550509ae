"""Optimality criteria of a layout's information, with the bounds that certify them.

F is the Fisher information in the scaled parameters θ̃ = θ / (m₀, m₀L, m₀L²)
(model.py): σ(θ̃_k) is a relative error (mass against m₀, first moments against
m₀L, inertia against m₀L²), the same scaling as accuracy.worst_relative_std, so
the parameters are commensurate and F's eigenvalues can be compared. Three
criteria, each to be maximised:

* D: log det F (volume of the confidence ellipsoid);
* A: −tr F⁻¹ (minus the sum of the relative variances);
* E: λ_min(F), the worst conditioned direction: 1/√λ_min is the largest relative
  1-σ of any unit combination of parameters, the conditioning the paper's
  analysis is about (§2, "a careful analysis ... on the conditioning").

All three are concave in the selection weights z of F(z) = M₀ + Σ z_i A_iᵀA_i.
The bounds below hold for every selection within the budgets (and every relaxed
z); the D bound lives in relaxation.py (a Kiefer–Wolfowitz dual).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from massline.core.information import log_det


def a_value(F: np.ndarray) -> float:
    """−tr F⁻¹ (relative variances, dimensionless), −inf when F is singular."""
    w = np.linalg.eigvalsh((F + F.T) / 2)
    return float(-np.sum(1 / w)) if w[0] > 1e-12 * max(w[-1], 1e-300) else -np.inf


def e_value(F: np.ndarray) -> float:
    """λ_min(F), the smallest eigenvalue of the scaled information (1 / relative variance)."""
    return float(np.linalg.eigvalsh((F + F.T) / 2)[0])


def d_scores(blocks: np.ndarray, M: np.ndarray) -> np.ndarray:
    """log det(M + A_iᵀA_i) for every block (the matrix determinant lemma, r × r)."""
    K = blocks @ np.linalg.inv(M) @ blocks.transpose(0, 2, 1) + np.eye(blocks.shape[1])
    sign, value = np.linalg.slogdet(K)
    return log_det(M) + np.where(sign > 0, value, -np.inf)


def a_scores(blocks: np.ndarray, M: np.ndarray) -> np.ndarray:
    """−tr (M + A_iᵀA_i)⁻¹ by Woodbury: −tr M⁻¹ + tr((I + A M⁻¹Aᵀ)⁻¹ A M⁻²Aᵀ) (rank-r update)."""
    M_inv = np.linalg.inv(M)
    T = blocks @ M_inv
    K = T @ blocks.transpose(0, 2, 1) + np.eye(blocks.shape[1])
    return -np.trace(M_inv) + np.einsum("nrr->n", np.linalg.solve(K, T @ T.transpose(0, 2, 1)))


def e_scores(blocks: np.ndarray, M: np.ndarray) -> np.ndarray:
    """λ_min(M + A_iᵀA_i) for every block (p × p eigenvalues, batched)."""
    return np.linalg.eigvalsh(M + np.einsum("nrp,nrq->npq", blocks, blocks))[:, 0]


def top_sum(problem, scores: np.ndarray) -> float:
    """max over selections within the budgets of Σ_{i∈S} s_i: the k_g largest s_i of each group g."""
    total = 0.0
    for g, k in enumerate(problem.budgets):
        in_group = np.sort(scores[problem.group == g])
        total += in_group[len(in_group) - k :].sum() if k else 0.0
    return total


def a_bound(problem, M: np.ndarray) -> float:
    """An upper bound on −tr F⁻¹ over the selections, from any M ≻ 0.

    Proof: for X, Y ≻ 0, tr X⁻¹ + tr(Y X) ≥ 2 tr Y^½ (equality at X = Y^−½).
    With Y = t M⁻², −tr X⁻¹ ≤ t tr(M⁻² X) − 2√t tr M⁻¹. For X = F(z) within the
    budgets, tr(M⁻²X) ≤ S = tr(M⁻²M₀) + top_sum(‖A_i M⁻¹‖²_F). Minimising over t:
    −tr X⁻¹ ≤ −(tr M⁻¹)² / S. At the relaxed optimum (KKT) it equals the relaxed value.
    """
    M_inv = np.linalg.inv(M)
    c = np.einsum("nrp,nrp->n", problem.blocks @ M_inv, problem.blocks @ M_inv)
    S = np.trace(M_inv @ M_inv @ problem.fixed) + top_sum(problem, c)
    return float(-(np.trace(M_inv) ** 2) / S)


def e_bound(problem, W: np.ndarray) -> float:
    """An upper bound on λ_min(F) over the selections, from any W ⪰ 0 (normalised to tr W = 1).

    Proof: λ_min(X) = min over tr W = 1, W ⪰ 0 of tr(W X) ≤ tr(W X) for this W, and
    tr(W F(z)) = tr(W M₀) + Σ z_i tr(W A_iᵀA_i) ≤ tr(W M₀) + top_sum(tr(W A_iᵀA_i)).
    The SDP dual; equal to the relaxed optimum at its optimal W.
    """
    w, V = np.linalg.eigh((W + W.T) / 2)
    root = V * np.sqrt(np.clip(w, 0, None) / np.clip(w, 0, None).sum())
    c = np.einsum("nrp,nrp->n", problem.blocks @ root, problem.blocks @ root)
    return float(np.trace(root.T @ problem.fixed @ root) + top_sum(problem, c))


@dataclass(frozen=True)
class Criterion:
    """A criterion: its value of F, the value after adding each block, and its efficiency.

    ``efficiency(value, bound)`` is the criterion's natural efficiency against the
    best layout, bounded below by using the upper bound U for the best value:
    D: exp((log det F − U)/p) per parameter; A: tr F_best⁻¹ / tr F⁻¹ ≥ U / value;
    E: λ_min(F) / λ_min(F_best) ≥ value / U.
    """

    name: str
    title: str
    value: Callable[[np.ndarray], float]
    scores: Callable[[np.ndarray, np.ndarray], np.ndarray]
    efficiency: Callable[[float, float, int], float]

    def __reduce__(self):
        """Pickled by name: a plan read back holds the one criterion of that name (``criterion is D`` holds)."""
        return named_criterion, (self.name,)


D = Criterion("D", "log det F", log_det, d_scores, lambda v, U, p: float(np.exp((v - U) / p)))
A = Criterion("A", "−tr F⁻¹", a_value, a_scores, lambda v, U, p: float(U / v) if v < 0 else 0.0)
E = Criterion("E", "λ_min(F)", e_value, e_scores, lambda v, U, p: float(v / U) if U > 0 else 0.0)
CRITERIA = {c.name: c for c in (D, A, E)}


def named_criterion(name: str) -> Criterion:
    """The criterion called ``name`` ("D", "A" or "E")."""
    return CRITERIA[name]
