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
highest-leverage candidates, which scales to 1e5 candidates. Small budgets leave
the relaxation loose: certificate.py tightens it.
"""

from __future__ import annotations

import numpy as np

from massline.core.information import log_det
from massline.placement.selection import BlockProblem, leverages
from massline.placement.work import Work


def upper_bound(problem: BlockProblem, M: np.ndarray, c: np.ndarray | None = None) -> float:
    """U: no selection (nor relaxed weights) within the budgets can exceed it."""
    M_inv = np.linalg.inv(M)
    c = leverages(problem.blocks, M_inv) if c is None else c
    S = np.trace(M_inv @ problem.fixed)
    for g, k in enumerate(problem.budgets):
        in_group = np.sort(c[problem.group == g])
        S += in_group[len(in_group) - k :].sum() if k else 0.0
    return log_det(M) + problem.p * np.log(S / problem.p)


def _line_search(M: np.ndarray, D: np.ndarray, alpha_max: float) -> float:
    """argmax over [0, α_max] of log det(M + α D) = log det M + Σ log(1 + α λ_k).

    λ are the eigenvalues of M⁻¹ D (at most 2r are non-zero); the slope
    Σ λ_k / (1 + α λ_k) decreases, so its root is found by safeguarded Newton.
    """
    lam = np.linalg.eigvals(np.linalg.solve(M, D)).real
    lam = [float(v) for v in lam if abs(v) > 1e-14 * max(np.abs(lam).max(), 1e-300)]
    shrinking = [v for v in lam if v < 0]
    if shrinking and alpha_max >= -1 / min(shrinking):  # M + α_max D singular: stop short of it
        alpha_max = (1 - 1e-9) * (-1 / min(shrinking))

    def slope(a):
        return sum(v / (1 + a * v) for v in lam)

    if slope(alpha_max) >= 0:
        return alpha_max
    lo, hi, a = 0.0, alpha_max, 0.5 * alpha_max
    for _ in range(50):
        g = slope(a)
        if abs(g) < 1e-12 * sum(abs(v) for v in lam) or hi - lo < 1e-15 * alpha_max:
            break
        lo, hi = (a, hi) if g > 0 else (lo, a)
        curvature = sum(v * v / (1 + a * v) ** 2 for v in lam)
        newton = a + g / curvature
        a = newton if lo < newton < hi else 0.5 * (lo + hi)
    return a


def feasible_weights(problem: BlockProblem, z: np.ndarray) -> np.ndarray:
    """Scale weights group by group (capped at 1) so that each group sums to its budget."""
    z = np.clip(z, 0, 1).astype(float)
    for g, k in enumerate(problem.budgets):
        members = np.flatnonzero(problem.group == g)
        w = z[members]
        if k == 0 or len(members) == 0:
            z[members] = 0.0
            continue
        if np.count_nonzero(w) < k:
            w = w + k / len(members)
        lo, hi = 0.0, k / max(w[w > 0].min(), 1e-300)
        for _ in range(50):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if np.minimum(1, mid * w).sum() < k else (lo, mid)
        z[members] = np.minimum(1, hi * w)
    return z


def relax_first_order(
    problem: BlockProblem,
    start=(),
    weights: np.ndarray | None = None,
    *,
    tol: float = 1e-4,
    max_iter: int = 5000,
    working_size: int = 400,
    refresh: int = 25,
    stop_below: float = -np.inf,
    stop_above: float = np.inf,
    work: Work | None = None,
    until: int | None = None,
) -> tuple[np.ndarray, float]:
    """Pairwise Frank–Wolfe on the relaxation, from the selection ``start`` (or ``weights``).

    Each step moves weight, within one budget group, from the chosen candidate of
    least leverage to the open candidate of most, by the exact line search. Steps
    run on a working set (the support plus the ``working_size`` highest
    leverages per group), refreshed with the full leverages every ``refresh``
    steps, when the bound over all candidates is evaluated. It stops when the
    bound is within ``tol`` of the relaxed value, falls to ``stop_below``, or the
    relaxed value passes ``stop_above`` (branch and bound needs no more), or when ``work`` (one unit a step)
    reaches ``until`` (default its limit). Returns the weights and the certified bound U.
    """
    n = len(problem.blocks)
    if weights is None:
        z = np.zeros(n)
        z[list(start)] = 1.0
    else:
        z = feasible_weights(problem, weights)

    def information(z):
        support = np.flatnonzero(z > 0)
        A = problem.blocks[support] * np.sqrt(z[support])[:, None, None]
        return problem.fixed + np.einsum("nrp,nrq->pq", A, A)

    M = information(z)
    if np.linalg.cond(M) > 1e12:  # a singular start: spread the budgets evenly instead
        z = feasible_weights(problem, np.zeros(n))
        M = information(z)
        if np.linalg.cond(M) > 1e12:
            return z, -np.inf  # no selection within the budgets is regular
    best_bound = np.inf
    for iteration in range(max_iter):
        if iteration % refresh == 0:
            M = information(z)  # afresh, so that rounding does not accumulate
            c_all = leverages(problem.blocks, np.linalg.inv(M))
            best_bound = min(best_bound, upper_bound(problem, M, c_all))
            value = log_det(M)
            if best_bound - value < tol or best_bound <= stop_below or value >= stop_above:
                break
            if work is not None and work.reached(until):
                break
            if np.linalg.cond(M) > 1e13:  # rounding has caught up with the iterate: keep the bound so far
                break
            active = np.flatnonzero(z > 0)
            for g in range(len(problem.budgets)):
                members = np.flatnonzero(problem.group == g)
                active = np.union1d(active, members[np.argsort(c_all[members])[-working_size:]])
        if work is not None:
            work.tally()
        c = leverages(problem.blocks[active], np.linalg.inv(M))
        step = None
        for g in range(len(problem.budgets)):
            in_g = problem.group[active] == g
            towards, away = in_g & (z[active] < 1), in_g & (z[active] > 0)
            if towards.any() and away.any():
                j, i = np.argmax(np.where(towards, c, -np.inf)), np.argmin(np.where(away, c, np.inf))
                if step is None or c[j] - c[i] > step[0]:
                    step = (c[j] - c[i], active[i], active[j])
        if step is None or step[0] <= 1e-12:
            break
        _, i, j = step
        D = problem.blocks[j].T @ problem.blocks[j] - problem.blocks[i].T @ problem.blocks[i]
        alpha = _line_search(M, D, min(z[i], 1 - z[j]))
        z[i] -= alpha
        z[j] += alpha
        M = M + alpha * D
    return z, min(best_bound, upper_bound(problem, information(z)))


def relax_cvxpy(problem: BlockProblem, solver: str | None = None, **options) -> tuple[np.ndarray, float]:
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
    cp.Problem(cp.Maximize(cp.log_det((M + M.T) / 2)), constraints).solve(solver=solver, **options)
    weights = np.clip(np.asarray(z.value).ravel(), 0, 1)
    M_value = problem.fixed + (K @ weights).reshape(p, p)
    return weights, upper_bound(problem, M_value)
