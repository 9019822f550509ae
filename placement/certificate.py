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

The branch and bound closes nodes against the best *admissible* selection it knows:
the certificate is of the planner's layout, and closing against an inadmissible
one (a kinematic step of κ(S̃) in the thousands, which D-optimality alone likes)
would stop it short of the target it states. Its bound still covers every selection.
"""

from __future__ import annotations

import itertools
from typing import Callable

import numpy as np

from massline.placement.cell_bound import BranchAndBound, branch_and_bound
from massline.placement.relaxation import relax_cvxpy, relax_first_order
from massline.placement.selection import BlockProblem, greedy, swap
from massline.placement.work import DEFAULT_STEPS, STEPS, Work

MIN_SHARE = 50  # relaxation steps a split problem gets at least
TARGETS = (0.96, 0.99)  # branch and bound closes nodes within these certified efficiencies in turn


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
    *,
    work: Work,
    until: int | None = None,
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
    relaxation, already solved, where the branch and bound's root starts. It stops when ``work`` (relaxation
    steps) reaches ``until`` (default its limit); each split problem gets an equal share of what is left.
    """
    deadline = work.limit if until is None else until
    bound, best = branch_and_bound(
        problem, chosen, slack, work=work, until=deadline, root_bound=root_bound, root_weights=root_weights
    )
    if problem.value(best) <= problem.value(chosen) + 1e-9 or admissible(best) or depth == 0:
        return bound, best if admissible(best) else list(chosen)
    cover = cover_for(best)
    if cover is None and not work.reached(deadline):  # no cut known: close nodes against admissible bests only
        found, best = branch_and_bound(
            problem, chosen, slack, work=work, until=deadline, root_bound=bound, admissible=admissible
        )
        return min(bound, found), best
    if cover is None or work.reached(deadline):
        return bound, list(chosen)
    bounds, winner = [], list(chosen)
    parts = split_by_cover(problem, cover)
    for part in parts:
        if work.reached(deadline):  # unfinished: the uncut bound is what stands
            return bound, winner
        start = swap(part, greedy(part))
        if not admissible(start):
            start = list(chosen) if _fits(part, chosen) else start
        share = work.spent + max((deadline - work.spent) // len(parts), MIN_SHARE)
        part_bound, part_best = certify_admissible(
            part, start, slack, admissible, cover_for, work=work, until=share, depth=depth - 1
        )
        bounds.append(part_bound)
        if admissible(part_best) and part.value(part_best) > problem.value(winner):
            winner = part_best
    return min(max(bounds, default=-np.inf), bound), winner


def _fits(problem: BlockProblem, chosen: list) -> bool:
    counts = np.bincount(problem.group[list(chosen)], minlength=len(problem.budgets))
    return bool(np.all(counts == np.asarray(problem.budgets)))


class SideBound:
    """One side's upper bound U over its admissible selections, tightened on demand, and the best one met.

    U = min(relaxation, branch and bound, cover cuts), each a true upper bound. The branch
    and bound counts as the best known only admissible selections, so that nodes close
    within a target of a layout the planner may adopt; it aims at each of ``targets`` in
    turn (a near target closes nodes and screens candidates sooner), starting again from
    the root for the next. When it meets an inadmissible selection above its target for
    which a cut is known (a motion it leaves unseen), the cuts take over
    (:func:`certify_admissible`). ``tighten`` may be called again and again.
    """

    def __init__(
        self, problem, chosen, relaxation="first-order", *, admissible=None, cover_for=None, targets=TARGETS, work=None
    ):
        self.problem, self.chosen = problem, list(chosen)
        self.work = Work(DEFAULT_STEPS, STEPS) if work is None else work
        self.admissible = admissible or (lambda c: True)
        self.cover_for, self.covers = cover_for or (lambda c: None), {}
        self.slacks = [problem.p * np.log(1 / target) for target in targets]
        self.cut, self.cut_best = np.inf, None
        if relaxation == "cvxpy":
            self.root, self.search = relax_cvxpy(problem)[1], None
            return
        self.weights, self.root = relax_first_order(problem, chosen, tol=1e-3)
        self.search = self._search(self.slacks[0], self.chosen, self.root)

    def _search(self, slack: float, start: list, bound: float) -> BranchAndBound:
        return BranchAndBound(
            self.problem,
            start,
            slack,
            root_bound=bound,
            root_weights=self.weights,
            admissible=self.admissible,
            any_slack=self.slacks[-1],
            work=self.work,
        )

    @property
    def bound(self) -> float:
        searched = np.inf if self.search is None else self.search.bound
        return min(self.root, self.cut, searched)

    @property
    def best(self) -> list:
        met = [self.chosen] + [s for s in (self.search and self.search.best, self.cut_best) if s]  # admissible
        return max(met, key=self.problem.value)

    @property
    def finished(self) -> bool:
        return (
            self.search is None
            or (self.search.finished and self.search.slack <= self.slacks[-1])
            or np.isfinite(self.cut)
            or self.bound <= self.problem.value(self.best) + self.slacks[-1]
        )

    def tighten(self, until: int | None = None, deadline: int | None = None) -> None:
        """Branch and bound until its work reaches ``until`` (relaxation steps; default its limit), a node's
        relaxation on to ``deadline`` (default ``until``); the cuts when it needs them."""
        deadline = until if deadline is None else deadline
        while not self.finished and not self.work.reached(until):
            if self.search.finished:  # this target is met: the next, from the root at the bound reached
                slack = next(s for s in self.slacks if s < self.search.slack)
                self.search = self._search(slack, self.best, self.bound)
            self.search.run(until, deadline, stop=self._needs_cut)
            if self._needs_cut():
                self.cut, winner = certify_admissible(
                    self.problem,
                    self.best,
                    self.search.slack,
                    self.admissible,
                    self.cover_for,
                    work=self.work,
                    until=deadline,
                )
                self.cut_best = winner if self.admissible(winner) else None

    def _needs_cut(self) -> bool:
        """The best selection met is inadmissible, beyond the slack, and a cut excludes it."""
        value, selection = self.search.best_any
        if value <= self.search.best_value + self.search.slack or self.admissible(selection):
            return False
        key = tuple(selection)
        if key not in self.covers:
            self.covers[key] = self.cover_for(selection) is not None
        return self.covers[key]


def certify(
    problem: BlockProblem,
    chosen: list,
    relaxation: str = "first-order",
    admissible=None,
    cover_for=None,
    steps: int = DEFAULT_STEPS,
) -> tuple[float, list]:
    """Upper bound U on ``problem`` over the admissible selections, and the best one met (:class:`SideBound`
    tightened for ``steps`` relaxation steps)."""
    side = SideBound(problem, chosen, relaxation, admissible=admissible, cover_for=cover_for, work=Work(steps, STEPS))
    side.tighten()
    return side.bound, side.best
