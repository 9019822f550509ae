"""The convex relaxation of the selection, and the bound it certifies.

Relaxed problem (Joshi & Boyd 2009), for weights 0 ≤ z_i ≤ 1 with Σ_{i∈g} z_i = k_g
in each budget group g:

    maximise  log det M(z),   M(z) = M₀ + Σ_i z_i A_iᵀ A_i.

Its optimum bounds every selection from above. For any z, with c_i = tr(A_i M(z)⁻¹ A_iᵀ),

    U(z) = log det M(z) + p · log(S(z) / p),   S = tr(M(z)⁻¹ M₀) + Σ_g (sum of the k_g largest c_i in g)

is an upper bound too (the dual with W = t M(z)⁻¹, t optimal; planning notes §8.2),
tight at the relaxed optimum. Two solvers: cvxpy's generic conic ``log_det`` (the
baseline, small sets), and a pairwise Frank–Wolfe (vertex exchange) with exact
line search, warm-started at a good selection and run on a working set of the
highest-leverage candidates, which scales to 1e5 candidates.
"""
from __future__ import annotations

import time

import numpy as np

from .information import log_det
from .selection import BlockProblem, greedy


def leverages(blocks: np.ndarray, M_inv: np.ndarray) -> np.ndarray:
    """c_i = tr(A_i M⁻¹ A_iᵀ) for every block."""
    return np.einsum("nrp,nrp->n", blocks @ M_inv, blocks)


def upper_bound(problem: BlockProblem, M: np.ndarray, c: np.ndarray | None = None) -> float:
    """U: no selection (nor relaxed weights) within the budgets can exceed it."""
    M_inv = np.linalg.inv(M)
    c = leverages(problem.blocks, M_inv) if c is None else c
    S = np.trace(M_inv @ problem.fixed)
    for g, k in enumerate(problem.budgets):
        in_group = np.sort(c[problem.group == g])
        S += in_group[len(in_group) - k:].sum() if k else 0.0
    return log_det(M) + problem.p * np.log(S / problem.p)


def _line_search(M: np.ndarray, D: np.ndarray, alpha_max: float) -> float:
    """argmax over [0, α_max] of log det(M + α D) (concave in α)."""
    lam = np.linalg.eigvals(np.linalg.solve(M, D)).real  # those of M^-1/2 D M^-1/2
    lam = lam[np.abs(lam) > 1e-14 * max(np.abs(lam).max(), 1e-300)]

    def slope(a):
        return np.sum(lam / (1 + a * lam))

    if slope(alpha_max) >= 0:
        return alpha_max
    lo, hi = 0.0, alpha_max
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if slope(mid) > 0 else (lo, mid)
    return lo


def relax_first_order(problem: BlockProblem, start, tol: float = 1e-4, max_iter: int = 5000,
                      working_size: int = 400, refresh: int = 25) -> tuple[np.ndarray, float]:
    """Pairwise Frank–Wolfe on the relaxation, from the selection ``start``.

    Each step moves weight, within one budget group, from the chosen candidate of
    least leverage to the open candidate of most, by the exact line search. Steps
    run on a working set (the support plus the ``working_size`` highest
    leverages per group), refreshed with the full leverages every ``refresh``
    steps, when the bound over all candidates is evaluated. Returns the weights
    and the certified bound U.
    """
    n, p = len(problem.blocks), problem.p
    z = np.zeros(n)
    z[list(start)] = 1.0
    M = problem.information(list(start))
    if np.linalg.cond(M) > 1e12:  # a singular start: spread the budgets evenly instead
        counts = np.bincount(problem.group, minlength=len(problem.budgets))
        z = np.asarray(problem.budgets, dtype=float)[problem.group] / counts[problem.group]
        M = problem.fixed + np.einsum("n,nrp,nrq->pq", z, problem.blocks, problem.blocks)
        if np.linalg.cond(M) > 1e12:
            return z, -np.inf  # no selection within the budgets is regular
    G = lambda i: problem.blocks[i].T @ problem.blocks[i]  # noqa: E731
    best_bound = np.inf
    def information(z):
        support = np.flatnonzero(z > 0)
        A = problem.blocks[support] * np.sqrt(z[support])[:, None, None]
        return problem.fixed + np.einsum("nrp,nrq->pq", A, A)

    for iteration in range(max_iter):
        if iteration % refresh == 0:
            M = information(z)  # afresh, so that rounding does not accumulate
            M_inv = np.linalg.inv(M)
            c_all = leverages(problem.blocks, M_inv)
            best_bound = min(best_bound, upper_bound(problem, M, c_all))
            if best_bound - log_det(M) < tol:
                break
            work = np.flatnonzero(z > 0)
            for g in range(len(problem.budgets)):
                members = np.flatnonzero(problem.group == g)
                top = members[np.argsort(c_all[members])[-working_size:]]
                work = np.union1d(work, top)
        c = leverages(problem.blocks[work], np.linalg.inv(M))
        step = None
        for g in range(len(problem.budgets)):
            in_g = problem.group[work] == g
            towards = in_g & (z[work] < 1)
            away = in_g & (z[work] > 0)
            if not towards.any() or not away.any():
                continue
            j = work[towards][np.argmax(c[towards])]
            i = work[away][np.argmin(c[away])]
            gap = c[work == j][0] - c[work == i][0]
            if step is None or gap > step[0]:
                step = (gap, i, j)
        if step is None or step[0] <= 1e-12:
            best_bound = min(best_bound, upper_bound(problem, M))
            break
        _, i, j = step
        D = G(j) - G(i)
        alpha = _line_search(M, D, min(z[i], 1 - z[j]))
        z[i] -= alpha
        z[j] += alpha
        M = M + alpha * D
    return z, min(best_bound, upper_bound(problem, M))


def relax_cvxpy(problem: BlockProblem, solver: str | None = None) -> tuple[np.ndarray, float]:
    """The same relaxation as written on paper, solved by a generic conic solver.

    The bound is re-evaluated at the returned weights, so it holds even when the
    solver's answer is slightly infeasible.
    """
    import cvxpy as cp

    n, p = len(problem.blocks), problem.p
    K = np.einsum("nrp,nrq->pqn", problem.blocks, problem.blocks).reshape(p * p, n)
    z = cp.Variable(n)
    M = problem.fixed + cp.reshape(K @ z, (p, p), order="C")
    constraints = [z >= 0, z <= 1]
    constraints += [cp.sum(z[np.flatnonzero(problem.group == g)]) == k for g, k in enumerate(problem.budgets)]
    cp.Problem(cp.Maximize(cp.log_det((M + M.T) / 2)), constraints).solve(solver=solver)
    weights = np.clip(np.asarray(z.value).ravel(), 0, 1)
    M_value = problem.fixed + (K @ weights).reshape(p, p)
    return weights, upper_bound(problem, M_value)


def _restrict(problem: BlockProblem, inside: frozenset, outside: frozenset):
    """The sub-problem with ``inside`` chosen (into M₀) and ``outside`` removed; None if infeasible."""
    budgets = np.array(problem.budgets)
    for i in inside:
        budgets[problem.group[i]] -= 1
    keep = np.ones(len(problem.blocks), dtype=bool)
    keep[list(inside | outside)] = False
    index = np.flatnonzero(keep)
    available = np.bincount(problem.group[index], minlength=len(budgets))
    if np.any(budgets < 0) or np.any(available < budgets):
        return None, index
    A = problem.blocks[list(inside)].reshape(-1, problem.p)
    return BlockProblem(problem.blocks[index], problem.group[index], tuple(budgets), problem.fixed + A.T @ A), index


def branch_and_bound(problem: BlockProblem, chosen, slack: float, max_nodes: int = 400,
                     tol: float = 1e-4, seconds: float = 10.0) -> tuple[float, list]:
    """A tighter certified bound: the relaxation's bounds over a partition of all selections.

    The selections are split by fixing the most fractional candidate in or out,
    depth first; a branch whose relaxation bound is within ``slack`` of the best
    selection known is closed with that bound. The certificate is the largest
    bound over the closed branches and, should ``max_nodes`` run out, over the
    parents of the open ones (likewise after ``seconds``). Small budgets (three exciters for ten parameters)
    leave the plain relaxation loose; this closes most of that gap honestly.
    Returns the bound and the best selection met (``chosen`` or better).
    """
    deadline = time.perf_counter() + seconds
    best_value, best = problem.value(chosen), list(chosen)
    certified = -np.inf
    stack = [(frozenset(), frozenset(), np.inf)]
    nodes = 0
    while stack:
        inside, outside, parent_bound = stack.pop()
        if nodes >= max_nodes or time.perf_counter() > deadline:
            certified = max(certified, parent_bound)
            continue
        nodes += 1
        sub, index = _restrict(problem, inside, outside)
        if sub is None:
            continue
        if sum(sub.budgets) == 0:
            value = log_det(sub.fixed)
            certified = max(certified, value)
            if value > best_value:
                best_value, best = value, sorted(inside)
            continue
        start = greedy(sub)
        value = sub.value(start)
        if value > best_value:
            best_value, best = value, sorted(inside | {int(index[s]) for s in start})
        z, bound = relax_first_order(sub, start, tol=tol)
        bound = min(bound, parent_bound)
        if bound <= best_value + slack:
            certified = max(certified, bound)
            continue
        open_ = (z > 1e-9) & (z < 1 - 1e-9)
        pick = int(index[np.argmax(np.where(open_, z, -1.0))]) if open_.any() else int(index[np.argmax(z)])
        stack.append((inside, outside | {pick}, bound))
        stack.append((inside | {pick}, outside, bound))
    return max(certified, best_value), best
