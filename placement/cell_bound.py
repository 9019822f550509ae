"""Branch and bound over cells of candidates, with screening: the D certificate at scale.

A node is a partition of the remaining candidates into cells, each with an exact
count to choose (a cell lies inside one budget group; the root has one cell per
group with its budget). Its relaxation (relaxation.relax_first_order with the
cells as budget groups) bounds every selection that meets the counts. A node is
split by cutting the cell whose relaxed weight is most spread into two halves
(along the principal axis of its support's information, entries of A_iᵀA_i),
one child per way of sharing the cell's count. With 1e5 dense candidates the
relaxation spreads each chosen line's weight over neighbours and over distinct
places; cutting cells removes exactly that, where branching on single candidates
(a near-duplicate excluded, another takes its place) never does.

Screening (Pronzato's delimitation of the support, budgeted): for the node's
relaxed M and c_i = tr(A_i M⁻¹ A_iᵀ), every selection containing candidate i
satisfies, for W = t M⁻¹ in the dual log det X ≤ −log det W − p + tr(W X),

    log det X ≤ U_i = log det M + p log(S_i / p),
    S_i = tr(M⁻¹M₀) + c_i + (k_g − 1 largest c in i's cell, i excluded) + Σ_other cells (k largest c),

(t = p / S_i). Candidates with U_i ≤ target are removed from the node's
children, and their largest U_i joins the closed bounds, so the certificate
stays a true upper bound: max(closed, open nodes, best value met).
"""

from __future__ import annotations

import heapq
import itertools

import numpy as np

from massline.core.information import log_det
from massline.placement.relaxation import relax_first_order
from massline.placement.selection import BlockProblem, leverages
from massline.placement.work import DEFAULT_STEPS, STEPS, Work


def _node_problem(problem: BlockProblem, cells: tuple) -> tuple[BlockProblem, np.ndarray]:
    """The node's problem (one budget group per cell) and the candidates it holds."""
    index = np.concatenate([c for c, _ in cells])
    group = np.concatenate([np.full(len(c), g) for g, (c, _) in enumerate(cells)])
    return BlockProblem(problem.blocks[index], group, tuple(m for _, m in cells), problem.fixed), index


def _warm_start(sub: BlockProblem, z: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The parent's weights; a cell short of support gets its count on its largest parent leverages."""
    w = z.copy()
    for g, m in enumerate(sub.budgets):
        members = np.flatnonzero(sub.group == g)
        if np.count_nonzero(w[members]) < m:
            w[members[np.argsort(-c[members])[:m]]] += 1.0
    return w


def screening_bounds(sub: BlockProblem, M: np.ndarray, c: np.ndarray) -> np.ndarray:
    """U_i for every candidate of the node: no selection holding i exceeds it (module docstring)."""
    S0 = np.trace(np.linalg.solve(M, sub.fixed))
    S_i = np.empty(len(c))
    tops = []
    for g, m in enumerate(sub.budgets):
        cg = np.sort(c[sub.group == g])[::-1]
        tops.append((cg[:m].sum(), cg[m - 1], cg[: m - 1].sum()))
    everything = S0 + sum(t[0] for t in tops)
    for g, (top, kth, top_less_one) in enumerate(tops):
        members = sub.group == g
        ci = c[members]
        S_i[members] = everything - top + ci + np.where(ci >= kth, top - ci, top_less_one)
    return log_det(M) + sub.p * np.log(np.maximum(S_i, 1e-300) / sub.p)


def _split(problem: BlockProblem, cells: list, z: np.ndarray) -> tuple | None:
    """The cell of most spread relaxed weight and its two halves (None when every cell is decided)."""
    best = None
    for g, (members, m) in enumerate(cells):
        weights = z[members]
        support = members[weights > 1e-6]
        if len(support) <= m:
            continue
        features = np.einsum("nrp,nrq->npq", problem.blocks[support], problem.blocks[support]).reshape(len(support), -1)
        w = z[support] / z[support].sum()
        mean = w @ features
        _, spread, axes = np.linalg.svd((features - mean) * np.sqrt(w)[:, None], full_matrices=False)
        if best is None or spread[0] > best[0]:
            best = (spread[0], g, axes[0], mean)
    if best is None:
        return None
    _, g, axis, mean = best
    members, m = cells[g]
    G = np.einsum("nrp,nrq->npq", problem.blocks[members], problem.blocks[members]).reshape(len(members), -1)
    side = (G - mean) @ axis > 0
    return g, members[~side], members[side]


def _rounded(z: np.ndarray, cells: list) -> list:
    """The integral selection nearest the relaxed weights: the largest m weights of each cell."""
    return [int(i) for members, m in cells for i in members[np.argsort(-z[members])[:m]]]


class BranchAndBound:
    """A certified upper bound on log det over the selections, tightened on demand, and the best selection met.

    ``root_bound`` and ``root_weights`` are a relaxation already solved on the whole problem
    (its bound, its weights per candidate): the root node starts from them. ``admissible``
    (a selection → bool), when given, limits the selections that become the best known;
    the best of all selections met, admissible or not, is kept beside it (``best_any``), and
    a node within ``any_slack`` of it closes too: no bound can fall below a selection's value,
    so splitting further would buy at most that slack.

    Best first: the open node of largest bound is relaxed, screened and split; a
    node whose bound is within ``slack`` of the best selection known is closed.
    At any moment ``bound`` = max(closed, open, best) bounds every selection and only
    falls, so the search may pause at any node and go on later (``run``).
    """

    def __init__(
        self,
        problem: BlockProblem,
        chosen,
        slack: float,
        *,
        tol: float = 1e-4,
        root_bound: float = np.inf,
        root_weights: np.ndarray | None = None,
        admissible=None,
        any_slack: float = -np.inf,
        work: Work | None = None,
    ):
        self.problem, self.slack, self.tol, self.admissible = problem, slack, tol, admissible
        self.work = Work(DEFAULT_STEPS, STEPS) if work is None else work
        self.any_slack = any_slack
        self.start, self.root_weights = list(chosen), root_weights
        self.best_value, self.best = problem.value(chosen), list(chosen)
        self.best_any = (self.best_value, self.best)
        root = tuple((np.flatnonzero(problem.group == g), k) for g, k in enumerate(problem.budgets) if k)
        self.heap = [(-root_bound, 0, root, None)]
        self.closed, self.nodes, self.tie = -np.inf, 0, itertools.count(1)

    @property
    def bound(self) -> float:
        still_open = max((-item[0] for item in self.heap), default=-np.inf)
        return max(self.closed, still_open, self.best_value)

    @property
    def finished(self) -> bool:
        return not self.heap

    @property
    def target(self) -> float:
        """Nodes whose bound is below this close."""
        return max(self.best_value + self.slack, self.best_any[0] + self.any_slack)

    def run(self, until: int | None = None, deadline: int | None = None, max_nodes: int = 100_000, stop=lambda: False):
        """Nodes until its work reaches ``until`` (relaxation steps; default its limit), ``max_nodes`` in all, the
        search ends or ``stop()``; a node's relaxation runs on to ``deadline`` (default ``until``)."""
        deadline = until if deadline is None else deadline
        while self.heap and self.nodes < max_nodes and not self.work.reached(until) and not stop():
            self._node(deadline)

    def _node(self, deadline: int | None) -> None:
        problem = self.problem
        negative_bound, _, cells, parent = heapq.heappop(self.heap)
        if -negative_bound <= self.target:  # the largest open bound: every open node closes
            self.closed, self.heap = max(self.closed, -negative_bound), []
            return
        self.nodes += 1
        sub, index = _node_problem(problem, cells)
        if parent is None:
            weights = None if self.root_weights is None else self.root_weights[index]
            start = [int(np.flatnonzero(index == i)[0]) for i in self.start]
        else:
            weights, start = _warm_start(sub, *parent), ()
        z, bound = relax_first_order(
            sub, start, weights, tol=self.tol, stop_below=self.target, work=self.work, until=deadline
        )
        bound = min(bound, -negative_bound)
        groups = [(np.flatnonzero(sub.group == g), m) for g, m in enumerate(sub.budgets)]
        self._met(sorted(int(index[i]) for i in _rounded(z, groups)))
        if bound <= self.target:
            self.closed = max(self.closed, bound)
            return
        M = sub.fixed + np.einsum("n,nrp,nrq->pq", z, sub.blocks, sub.blocks)
        c = leverages(sub.blocks, np.linalg.inv(M))
        U_i = screening_bounds(sub, M, c)
        screened = U_i <= self.target
        self.closed = max(self.closed, U_i[screened].max(initial=-np.inf))
        z_all, c_all = np.zeros(len(problem.blocks)), np.zeros(len(problem.blocks))
        z_all[index], c_all[index] = z, c
        kept = [(index[(sub.group == g) & ~screened], m) for g, m in enumerate(sub.budgets)]
        if any(len(members) < m for members, m in kept):
            return  # no selection of the node survives screening: its bound is the screened one
        split = _split(problem, kept, z_all)
        if split is None:
            self.closed = max(self.closed, bound)
            return
        g, left, right = split
        m = kept[g][1]
        for j in range(m + 1):
            if len(left) >= j and len(right) >= m - j:
                child = tuple((c_, k) for c_, k in kept[:g] + [(left, j), (right, m - j)] + kept[g + 1 :] if k)
                held = np.concatenate([c_ for c_, _ in child])
                heapq.heappush(self.heap, (-bound, next(self.tie), child, (z_all[held], c_all[held])))

    def _met(self, selection: list) -> None:
        value = self.problem.value(selection)
        if value > self.best_any[0]:
            self.best_any = (value, selection)
        if value > self.best_value and (self.admissible is None or self.admissible(selection)):
            self.best_value, self.best = value, selection


def branch_and_bound(
    problem: BlockProblem,
    chosen,
    slack: float,
    *,
    max_nodes: int = 100_000,
    tol: float = 1e-4,
    work: Work | None = None,
    until: int | None = None,
    root_bound: float = np.inf,
    root_weights: np.ndarray | None = None,
    admissible=None,
) -> tuple[float, list]:
    """:class:`BranchAndBound` run until ``work`` reaches ``until`` (relaxation steps; default its limit) or
    ``max_nodes``: its bound and best selection."""
    search = BranchAndBound(
        problem, chosen, slack, tol=tol, root_bound=root_bound, root_weights=root_weights, admissible=admissible,
        work=work,
    )  # fmt: skip
    search.run(until, max_nodes=max_nodes)
    return search.bound, search.best
