"""Certified bounds for small budgets: branch and bound, and admissibility cuts.

With six sensors or three exciters for ten parameters the relaxation's bound
(relaxation.py) can sit 1 nat above the best selection. Two honest tightenings:

* branch and bound over cells of candidates, each node bounded by its relaxation,
  with screening (cell_bound.py);
* cuts that every admissible layout satisfies: a layout the paper's equations
  can solve sees every rigid motion q, so for a motion q₀ that some selection
  leaves unseen, at least one chosen candidate must see it (ℓ · q₀ ≠ 0). The
  bound over admissible layouts is the largest over how many candidates come
  from that cover set.
"""

from __future__ import annotations

import itertools
import time
from typing import Callable

import numpy as np

from massline.placement.cell_bound import branch_and_bound
from massline.placement.relaxation import relax_cvxpy, relax_first_order
from massline.placement.selection import BlockProblem, greedy, swap

TARGETS = (0.95, 0.99)  # branch and bound aims at these certified efficiencies in turn


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
    root_weights: np.ndarray | None = None,
) -> tuple[float, list]:
    """An upper bound over the admissible selections, and the best admissible one met.

    Branch and bound first; if the best selection it meets is not admissible,
    ``cover_for`` names the candidates any admissible layout must draw on (None:
    no cut is known, the plain bound stands) and the bound is the largest over the
    split problems, each certified the same way (``depth`` levels of cuts). A
    bound over all selections holds for the admissible ones too, so the smaller
    of the two is returned. ``root_bound`` and ``root_weights``: the whole problem's
    relaxation, already solved, where the branch and bound's root starts.
    """
    deadline = time.perf_counter() + seconds
    bound, best = branch_and_bound(
        problem, chosen, slack, seconds=seconds, root_bound=root_bound, root_weights=root_weights
    )
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
    targets: tuple = TARGETS,
) -> tuple[float, list]:
    """Upper bound U on ``problem`` over the admissible selections, and the best one met.

    The relaxation's bound first; when it leaves the per-parameter D-efficiency
    below the last of ``targets`` (small budgets), branch and bound and admissibility
    cuts tighten it, aiming at each target in turn (a near target closes nodes
    sooner) while time remains; every bound met is valid, the least is returned.
    """
    if relaxation == "cvxpy":
        return relax_cvxpy(problem)[1], chosen
    deadline = time.perf_counter() + seconds
    weights, bound = relax_first_order(problem, chosen, tol=1e-3)
    for target in targets:
        slack = problem.p * np.log(1 / target)
        if bound - problem.value(chosen) <= slack or time.perf_counter() > deadline:
            continue
        found, chosen = certify_admissible(
            problem,
            chosen,
            slack,
            admissible or (lambda c: True),
            cover_for or (lambda c: None),
            deadline - time.perf_counter(),
            root_bound=bound,
            root_weights=weights,
        )
        bound = min(bound, found)
    return bound, chosen
