"""Certified bounds for the A and E criteria: the convex relaxation, by column generation.

The relaxation maximises the criterion over weights 0 ≤ z_i ≤ 1, Σ_{i∈g} z_i = k_g:

    A:  minimise tr F(z)⁻¹        (cvxpy ``tr_inv``),
    E:  maximise t  s.t.  F(z) ⪰ t I   (an SDP; its dual variable is W ⪰ 0, tr W = 1).

It is solved on a working set (the selection and the candidates of largest dual
score); the bound is then evaluated over every candidate from the solution
(criteria.a_bound from M = F(z), criteria.e_bound from the dual W), so it holds
whatever the working set left out; candidates whose dual score would raise the
bound join the working set and the solve repeats. Information is scaled to unit
mean eigenvalue for the conic solver and the results scaled back.
"""

from __future__ import annotations

import warnings

import numpy as np

from massline.placement.criteria import A, Criterion, a_bound, e_bound
from massline.placement.selection import BlockProblem

WORKING = 200  # candidates per group in the first working set


def _dual_scores(problem: BlockProblem, criterion: Criterion, M: np.ndarray, W: np.ndarray | None) -> np.ndarray:
    """The gradient of the bound in each candidate's weight: ‖A_i M⁻¹‖² (A) or tr(W A_iᵀA_i) (E)."""
    R = np.linalg.inv(M) if criterion is A else np.linalg.cholesky(W + 1e-12 * np.trace(W) * np.eye(len(W)))
    T = problem.blocks @ R
    return np.einsum("nrp,nrp->n", T, T)


def _working_set(problem: BlockProblem, scores: np.ndarray, keep, size: int) -> np.ndarray:
    work = set(int(i) for i in keep)
    for g in range(len(problem.budgets)):
        members = np.flatnonzero(problem.group == g)
        work |= set(members[np.argsort(-scores[members])[:size]].tolist())
    return np.array(sorted(work))


def _solve(problem: BlockProblem, criterion: Criterion, work: np.ndarray, scale: float):
    """The relaxation on the working set: F(z) (scaled back) and, for E, the dual W."""
    import cvxpy as cp

    p = problem.p
    blocks = problem.blocks[work] / np.sqrt(scale)
    K = np.einsum("nrp,nrq->pqn", blocks, blocks).reshape(p * p, len(work))
    z = cp.Variable(len(work))
    F = problem.fixed / scale + cp.reshape(K @ z, (p, p), order="C")
    F = (F + F.T) / 2
    constraints = [z >= 0, z <= 1]
    constraints += [cp.sum(z[np.flatnonzero(problem.group[work] == g)]) == k for g, k in enumerate(problem.budgets)]
    t = cp.Variable()
    lmi = F - t * np.eye(p) >> 0
    problem_ = (
        cp.Problem(cp.Minimize(cp.tr_inv(F)), constraints)
        if criterion is A
        else cp.Problem(cp.Maximize(t), constraints + [lmi])
    )
    with warnings.catch_warnings():  # an inaccurate solve is harmless: the bound is re-evaluated from it
        warnings.simplefilter("ignore")
        problem_.solve(solver="CLARABEL")
    W = None if criterion is A else np.asarray(lmi.dual_value)
    weights = np.clip(np.asarray(z.value).ravel(), 0, 1)
    return problem.fixed + scale * (K @ weights).reshape(p, p), W


def relax_criterion(problem: BlockProblem, criterion: Criterion, chosen, rounds: int = 4) -> float:
    """Upper bound U of ``criterion`` (A or E) over every selection within the budgets.

    Column generation: solve on the working set, evaluate the bound over all
    candidates, add the candidates of largest dual score, until the bound stops
    falling by more than 1e-3 of itself. The smallest bound met is returned (each is
    valid, the first one taken at the selection itself).
    """
    from cvxpy.error import SolverError

    M0 = problem.information(chosen) + problem.regulariser()
    scale = np.trace(M0) / problem.p
    w, V = np.linalg.eigh(M0)
    W = np.outer(V[:, 0], V[:, 0])
    scores = _dual_scores(problem, criterion, M0, W)
    work = _working_set(problem, scores, chosen, WORKING)
    best = a_bound(problem, M0) if criterion is A else e_bound(problem, W)
    for _ in range(rounds):
        try:
            F, W = _solve(problem, criterion, work, scale)
        except (SolverError, ArithmeticError, TypeError):  # solver failure: the bound so far stands
            break
        bound = a_bound(problem, F) if criterion is A else e_bound(problem, W)
        done = bound > best - 1e-3 * abs(best)
        best = min(best, bound)
        if done:
            break
        scores = _dual_scores(problem, criterion, F, W)
        work = np.union1d(work, _working_set(problem, scores, (), WORKING // 2))
    return best
