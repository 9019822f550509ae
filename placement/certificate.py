"""Certified bounds for small budgets: branch and bound, and admissibility cuts.

With six sensors or three exciters for ten parameters the relaxation's bound
(relaxation.py) can sit 1 nat above the best selection. Two honest tightenings:

* branch and bound over the selections, each branch bounded by its relaxation;
* cuts that every admissible layout satisfies: a layout the paper's equations
  can solve sees every rigid motion q, so for a motion q₀ that some selection
  leaves unseen, at least one chosen candidate must see it (ℓ · q₀ ≠ 0). The
  bound over admissible layouts is the largest over how many candidates come
  from that cover set.
"""

from __future__ import annotations

import heapq
import itertools
import time
from typing import Callable

import numpy as np

from massline.placement.information import log_det
from massline.placement.relaxation import relax_cvxpy, relax_first_order
from massline.placement.selection import BlockProblem, greedy, swap

TARGET_EFFICIENCY = 0.99  # branch and bound stops once the certificate reaches this


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


def branch_and_bound(
    problem: BlockProblem,
    chosen,
    slack: float,
    max_nodes: int = 100_000,
    tol: float = 1e-4,
    seconds: float = 10.0,
    root_bound: float = np.inf,
) -> tuple[float, list]:
    """A tighter certified bound: the relaxation's bounds over a partition of all selections.

    Best first: the open branch of largest bound is split by fixing its most
    decided fractional candidate in or out; a branch whose relaxation bound is
    within ``slack`` of the best selection known is closed. At any moment the
    largest bound over closed and open branches is a valid certificate, and it
    only falls, so the search can stop after ``seconds`` or ``max_nodes``.
    Small budgets (six sensors, three exciters for ten parameters) leave the plain
    relaxation loose; this closes most of that gap honestly. Returns the bound
    and the best selection met (``chosen`` or better).
    """
    deadline = time.perf_counter() + seconds
    best_value, best = problem.value(chosen), list(chosen)
    closed = -np.inf
    heap = [(-root_bound, 0, frozenset(), frozenset(), None)]  # (−parent bound, tie, in, out, parent weights)
    nodes = 0
    while heap:
        if nodes >= max_nodes or time.perf_counter() > deadline:
            break
        negative_bound, _, inside, outside, parent_z = heapq.heappop(heap)
        parent_bound = -negative_bound
        if parent_bound <= best_value + slack:  # every open branch is now within the slack
            closed = max(closed, parent_bound)
            heap = []
            break
        nodes += 1
        sub, index = _restrict(problem, inside, outside)
        if sub is None:
            continue
        if sum(sub.budgets) == 0:
            value = log_det(sub.fixed)
            closed = max(closed, value)
            if value > best_value:
                best_value, best = value, sorted(inside)
            continue
        start = greedy(sub) if parent_z is None else ()
        if parent_z is None and sub.value(start) > best_value:
            best_value, best = sub.value(start), sorted(inside | {int(index[s]) for s in start})
        target = best_value + slack
        z, bound = relax_first_order(
            sub,
            start,
            None if parent_z is None else parent_z[index],
            tol=tol,
            refresh=10,
            stop_below=target,
            stop_above=target,
            deadline=deadline,
        )
        bound = min(bound, parent_bound)
        if bound <= target:
            closed = max(closed, bound)
            continue
        open_ = (z > 1e-9) & (z < 1 - 1e-9)
        pick = int(index[np.argmax(np.where(open_, z, -1.0))]) if open_.any() else int(index[np.argmax(z)])
        full = np.zeros(len(problem.blocks))
        full[index] = z
        heapq.heappush(heap, (-bound, nodes * 2, inside | {pick}, outside, full))
        heapq.heappush(heap, (-bound, nodes * 2 + 1, inside, outside | {pick}, full))
    still_open = max((-item[0] for item in heap), default=-np.inf)
    return max(closed, still_open, best_value), best


def split_by_cover(problem: BlockProblem, cover: np.ndarray) -> list[BlockProblem]:
    """The problems 'exactly m_g candidates of group g from the cover', Σ m_g ≥ 1.

    Their selections are exactly those of ``problem`` that choose at least one
    candidate from ``cover``.
    """
    group = 2 * problem.group + cover.astype(int)
    ranges = []
    for g, k in enumerate(problem.budgets):
        in_cover = int(np.sum(cover & (problem.group == g)))
        outside = int(np.sum(~cover & (problem.group == g)))
        ranges.append([m for m in range(0, min(k, in_cover) + 1) if k - m <= outside])
    parts = []
    for ms in itertools.product(*ranges):
        if sum(ms) == 0:
            continue
        budgets = tuple(v for k, m in zip(problem.budgets, ms) for v in (k - m, m))
        parts.append(BlockProblem(problem.blocks, group, budgets, problem.fixed))
    return parts


def certify_admissible(
    problem: BlockProblem,
    chosen: list,
    slack: float,
    admissible: Callable[[list], bool],
    cover_for: Callable[[list], np.ndarray | None],
    seconds: float = 10.0,
    depth: int = 2,
    root_bound: float = np.inf,
) -> tuple[float, list]:
    """An upper bound over the admissible selections, and the best admissible one met.

    Branch and bound first; if the best selection it meets is not admissible,
    ``cover_for`` names the candidates any admissible layout must draw on (None:
    no cut is known, the plain bound stands) and the bound is the largest over the
    split problems, each certified the same way (``depth`` levels of cuts). A
    bound over all selections holds for the admissible ones too, so the smaller
    of the two is returned.
    """
    deadline = time.perf_counter() + seconds
    bound, best = branch_and_bound(problem, chosen, slack, seconds=seconds, root_bound=root_bound)
    if problem.value(best) <= problem.value(chosen) + 1e-9 or admissible(best) or depth == 0:
        return bound, best if admissible(best) else list(chosen)
    cover = cover_for(best)
    if cover is None or time.perf_counter() > deadline:
        return bound, list(chosen)
    bounds, winner = [], list(chosen)
    parts = split_by_cover(problem, cover)
    for part in parts:
        if time.perf_counter() > deadline:  # unfinished: the uncut bound is what stands
            return bound, winner
        start = swap(part, greedy(part))
        if not admissible(start):
            start = list(chosen) if _fits(part, chosen) else start
        remaining = max(deadline - time.perf_counter(), 0.05) / len(parts)
        part_bound, part_best = certify_admissible(part, start, slack, admissible, cover_for, remaining, depth - 1)
        bounds.append(part_bound)
        if admissible(part_best) and part.value(part_best) > problem.value(winner):
            winner = part_best
    return min(max(bounds, default=-np.inf), bound), winner


def _fits(problem: BlockProblem, chosen: list) -> bool:
    counts = np.bincount(problem.group[list(chosen)], minlength=len(problem.budgets))
    return bool(np.all(counts == np.asarray(problem.budgets)))


def certify(
    problem: BlockProblem,
    chosen: list,
    relaxation: str = "first-order",
    admissible=None,
    cover_for=None,
    seconds: float = 10.0,
) -> tuple[float, list]:
    """Upper bound U on ``problem`` over the admissible selections, and the best one met.

    The relaxation's bound first; when it leaves the per-parameter D-efficiency
    below TARGET_EFFICIENCY (small budgets), branch and bound and admissibility
    cuts tighten it (certificate.py).
    """
    if relaxation == "cvxpy":
        return relax_cvxpy(problem)[1], chosen
    _, bound = relax_first_order(problem, chosen, tol=1e-3)
    slack = problem.p * np.log(1 / TARGET_EFFICIENCY)
    if bound - problem.value(chosen) <= slack:
        return bound, chosen
    return certify_admissible(
        problem, chosen, slack, admissible or (lambda c: True), cover_for or (lambda c: None), seconds, root_bound=bound
    )
