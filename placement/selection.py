"""Choosing candidates that maximise log det of the information: greedy, swaps, EfI.

A selection problem holds one block of rows A_i (r × p) per candidate, whose
information is G_i = A_iᵀ A_i: a uniaxial sensor seen through the chosen
exciters, a triaxial sensor (three lines), or an exciter seen through the chosen
sensors. Candidates fall into budget groups (uniaxial, triaxial) with a count
each; information already fixed (instrumented points) is M₀. The criterion is

    f(S) = φ(M₀ + Σ_{i∈S} G_i),

φ one of criteria.py's: log det (D, the default), −tr(·)⁻¹ (A) or λ_min (E).
Greedy grows the selection by D (A and E are flat or infinite until the
information is regular, so a regular start is built by D, as is classical);
the exchanges then climb the problem's own criterion.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from massline.placement.criteria import Criterion, D
from massline.core.information import log_det


@dataclass(frozen=True, eq=False)
class BlockProblem:
    """Candidate blocks (n, r, p), their budget group (n,), budgets per group, fixed M₀ (p, p), criterion; which
    candidates may be chosen at all (``allowed`` (n,), None: all), and each one's point (``sites`` (n, 3) m) with
    the least distance (``spacing``, m) between two chosen ones (accelerometers a base apart, :mod:`.footprints`)."""

    blocks: np.ndarray
    group: np.ndarray
    budgets: tuple
    fixed: np.ndarray
    criterion: Criterion = D
    allowed: np.ndarray | None = None
    sites: np.ndarray | None = None
    spacing: float = 0.0

    @property
    def p(self) -> int:
        return self.blocks.shape[2]

    def information(self, chosen) -> np.ndarray:
        A = self.blocks[np.asarray(chosen, dtype=int)].reshape(-1, self.p)
        return self.fixed + A.T @ A

    def value(self, chosen) -> float:
        return self.criterion.value(self.information(chosen))

    def free(self, chosen, leaving: int | None = None) -> np.ndarray:
        """(n,) bool: the candidates that may join ``chosen`` once its position ``leaving`` (if any) has left:
        allowed, not chosen, and ``spacing`` from every chosen candidate that stays."""
        chosen = np.asarray(chosen, dtype=int)
        staying = chosen if leaving is None else np.delete(chosen, leaving)
        ok = np.ones(len(self.blocks), dtype=bool) if self.allowed is None else self.allowed.copy()
        if self.sites is not None and self.spacing > 0 and len(staying):
            gap = np.linalg.norm(self.sites[:, None, :] - self.sites[staying][None, :, :], axis=2)
            ok &= (gap >= self.spacing).all(axis=1)
        ok[chosen] = False
        return ok

    def regulariser(self) -> np.ndarray:
        """ε I, tiny against the candidates' information, so that log det is finite."""
        scale = np.einsum("nrp,nrp->", self.blocks, self.blocks) / max(len(self.blocks), 1) / self.p
        return 1e-9 * max(scale, np.trace(self.fixed) / self.p, 1e-300) * np.eye(self.p)


def gains(blocks: np.ndarray, M_inv: np.ndarray) -> np.ndarray:
    """log det(I + A_i M⁻¹ A_iᵀ) for every block: the gain of adding each."""
    T = blocks @ M_inv
    K = T @ blocks.transpose(0, 2, 1)
    K = K + np.eye(blocks.shape[1])
    sign, value = np.linalg.slogdet(K)
    return np.where(sign > 0, value, -np.inf)


def leverages(blocks: np.ndarray, M_inv: np.ndarray) -> np.ndarray:
    """c_i = tr(A_i M⁻¹ A_iᵀ) for every block; it bounds the gain: log det(I + K) ≤ tr K."""
    return np.einsum("nrp,nrp->n", blocks @ M_inv, blocks)


def best_gains(
    blocks: np.ndarray, M_inv: np.ndarray, allowed: np.ndarray, count: int = 1, floor: float = -np.inf, chunk: int = 512
) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` largest gains among allowed blocks (indices and values, best first).

    Exact, but lazy: blocks are evaluated in decreasing order of a bound on their
    gain, until no unevaluated block can enter the top ``count`` or beat ``floor``.
    With K = A_i M⁻¹ A_iᵀ the bound is the lesser of two: Σ_r log(1 + K_rr)
    (Hadamard: det(I + K) is at most the product of its diagonal), and
    Σ_k log(1 + ‖A_i v_k‖² / λ_k) over the eigenpairs of M (K = Σ_k K_k with
    K_k = A_i v_k v_kᵀ A_iᵀ / λ_k, and det(I + X + Y) ≤ det(I + X) det(I + Y) for
    X, Y ⪰ 0); the second is tight when M is nearly singular along a few directions,
    as after removing a chosen block. With 1e5 candidates a few hundred get evaluated.
    """
    lam, V = np.linalg.eigh(np.linalg.inv(M_inv))
    T = blocks @ (V / np.sqrt(np.maximum(lam, 1e-300)))
    hadamard = np.log1p(np.maximum(np.einsum("nrp,nrp->nr", T, T), 0)).sum(axis=1)
    eigen = np.log1p(np.einsum("nrk,nrk->nk", T, T)).sum(axis=1)
    bound = np.where(allowed, np.minimum(hadamard, eigen), -np.inf)
    order = np.argsort(-bound)
    order = order[np.isfinite(bound[order])]
    index, value = np.empty(0, dtype=int), np.empty(0)
    for start in range(0, len(order), chunk):
        batch = order[start : start + chunk]
        index = np.concatenate([index, batch])
        value = np.concatenate([value, gains(blocks[batch], M_inv)])
        keep = np.argsort(-value)[:count]
        index, value = index[keep], value[keep]
        threshold = max(value[-1] if len(value) == count else -np.inf, floor)
        if start + chunk >= len(order) or bound[order[start + chunk]] <= threshold:
            break
    return index, value


def best_scores(
    problem: BlockProblem, M: np.ndarray, allowed: np.ndarray, count: int, floor: float
) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` allowed blocks whose addition to M gives the largest criterion, and those values.

    D evaluates lazily (best_gains); A and E evaluate every allowed block.
    """
    if problem.criterion is D:
        index, gain = best_gains(problem.blocks, np.linalg.inv(M), allowed, count, floor - log_det(M))
        return index, log_det(M) + gain
    index = np.flatnonzero(allowed)
    values = problem.criterion.scores(problem.blocks[index], M)
    order = np.argsort(-values)[:count]
    return index[order], values[order]


def _open(problem: BlockProblem, chosen: list) -> np.ndarray:
    """Candidates that may still be added: free (:meth:`BlockProblem.free`), group budget not used up."""
    used = (
        np.bincount(problem.group[chosen], minlength=len(problem.budgets))
        if chosen
        else np.zeros(len(problem.budgets), int)
    )
    return (used[problem.group] < np.asarray(problem.budgets)[problem.group]) & problem.free(chosen)


def greedy(problem: BlockProblem, start=()) -> list:
    """Forward greedy: add the block of largest gain until every budget is spent."""
    chosen = list(start)
    M = problem.information(chosen) + problem.regulariser()
    while True:
        ok = _open(problem, chosen)
        if not ok.any():
            return chosen
        best = int(best_gains(problem.blocks, np.linalg.inv(M), ok)[0][0])
        chosen.append(best)
        M += problem.blocks[best].T @ problem.blocks[best]


def swap(
    problem: BlockProblem, chosen: list, admissible=None, tol: float = 1e-10, max_passes: int = 100, tries: int = 50
) -> list:
    """Best-improvement exchanges (Fedorov) within each budget group until none helps.

    ``admissible(chosen) -> bool`` restricts the selections swaps may reach (a
    layout the paper's equations can solve); from an inadmissible start, the
    best admissible exchange is taken whatever its value. For each chosen block
    the ``tries`` best exchanges are checked for admissibility; from an inadmissible
    start, ``tries`` checks in all (when the other side is what fails, none can
    succeed; settle's repair is the way out).
    """
    chosen = list(chosen)
    eps = problem.regulariser()
    ok_now = admissible is None or admissible(chosen)
    checks = itertools.count() if ok_now else iter(range(tries))
    for _ in range(max_passes):
        M = problem.information(chosen) + eps
        current = problem.criterion.value(M)
        best = (current + tol * max(abs(current), 1) if ok_now else -np.inf, None, None)
        for position, out in enumerate(chosen):
            reduced = M - problem.blocks[out].T @ problem.blocks[out]
            open_ = (problem.group == problem.group[out]) & problem.free(chosen, position)
            candidates, totals = best_scores(problem, reduced, open_, tries, best[0])
            for candidate, total in zip(candidates, totals):
                if total <= best[0]:
                    break
                trial = chosen[:position] + [int(candidate)] + chosen[position + 1 :]
                if next(checks, None) is None:
                    break
                if admissible is None or admissible(trial):
                    best = (total, position, int(candidate))
                    break
        if best[1] is None:
            return chosen
        chosen[best[1]] = best[2]
        ok_now, checks = True, itertools.count()
    return chosen


def repair(problem: BlockProblem, chosen: list, admissible, cover: np.ndarray, tries: int = 200, screen=None) -> list:
    """The best single exchange that brings in a candidate from ``cover`` and makes the
    selection admissible (``chosen`` unchanged when none does). ``screen(trials)``, when given, tells the
    trials that may be admissible (a boolean array), all evaluated together; only those are checked."""
    M = problem.information(chosen) + problem.regulariser()
    options = []
    for position, out in enumerate(chosen):
        reduced = M - problem.blocks[out].T @ problem.blocks[out]
        allowed = cover & (problem.group == problem.group[out]) & problem.free(chosen, position)
        index, gain = best_gains(problem.blocks, np.linalg.inv(reduced), allowed, tries)
        options += [(log_det(reduced) + g, position, int(i)) for i, g in zip(index, gain)]
    ranked = sorted(options, reverse=True)
    trials = [chosen[:position] + [candidate] + chosen[position + 1 :] for _, position, candidate in ranked]
    passing = np.ones(len(trials), bool) if screen is None else screen(trials)
    return next((trial for trial, ok in zip(trials, passing) if ok and admissible(trial)), list(chosen))


def effective_independence(problem: BlockProblem) -> list:
    """Kammer's EfI: delete the candidate of least leverage until the budgets are met.

    The leverage of block i is 1 − det(I − A_i F⁻¹ A_iᵀ), the fraction of det F
    lost without it (the triaxial form of SDynPy). Deletion stops in a group once
    its budget is reached. As commercial pre-test tools do, large sets lose 2.5 %
    of their removable candidates per step; the last hundred go one at a time.
    The classical backward baseline.
    """
    keep = list(range(len(problem.blocks)))
    budgets = np.asarray(problem.budgets)
    eps = problem.regulariser()
    while True:
        counts = np.bincount(problem.group[keep], minlength=len(budgets))
        removable = np.array([counts[problem.group[i]] > budgets[problem.group[i]] for i in keep])
        if not removable.any():
            return keep
        F_inv = np.linalg.inv(problem.information(keep) + eps)
        blocks = problem.blocks[keep]
        T = blocks @ F_inv @ blocks.transpose(0, 2, 1)
        sign, logdet_rest = np.linalg.slogdet(np.eye(blocks.shape[1]) - T)
        loss = 1 - np.where(sign > 0, np.exp(logdet_rest), 0.0)
        loss[~removable] = np.inf
        n_removable = int(removable.sum())
        batch = 1 if n_removable <= 100 else int(0.025 * n_removable)
        drop = set(np.argsort(loss)[:batch].tolist())
        keep = [c for position, c in enumerate(keep) if position not in drop]


def settle(problem: BlockProblem, chosen: list, admissible, cover_for, screen=None) -> list:
    """Exchanges to a local optimum among admissible selections; an inadmissible
    start is first repaired from the cover set of the motion it leaves unseen (``screen``: :func:`repair`'s)."""
    chosen = swap(problem, chosen, admissible)
    for _ in range(3):
        if admissible(chosen):
            break
        cover = cover_for(chosen)
        if cover is None:
            break
        chosen = swap(problem, repair(problem, chosen, admissible, cover, screen=screen), admissible)
    return chosen


def descend(
    problem: BlockProblem, chosen: list, violations, relief=None, tries: int = 50, max_passes: int = 30
) -> list:
    """Single exchanges that lower the violation (≥ 0; 0 when the selection is admissible), the most informative
    of equal violation first, until it is 0 or no exchange among each chosen block's ``tries`` best lowers it.
    The walk may pass through layouts the paper's equations cannot solve (a motion seen again may take two
    exchanges): its end is settled among admissible ones. ``violations(selections)`` evaluates a pass's trials
    together (an array); ``relief(selection)``, when given, marks candidates tried as well (their ``tries`` most
    informative): those the violation needs though they add little information."""
    chosen, now = list(chosen), float(violations([chosen])[0])
    eps = problem.regulariser()
    for _ in range(max_passes):
        if now <= 0:
            break
        M = problem.information(chosen) + eps
        extra = None if relief is None else relief(chosen)
        trials, information = [], []
        for position, out in enumerate(chosen):
            reduced = M - problem.blocks[out].T @ problem.blocks[out]
            open_ = (problem.group == problem.group[out]) & problem.free(chosen, position)
            base, inverse = log_det(reduced), np.linalg.inv(reduced)
            found = [best_gains(problem.blocks, inverse, open_, tries)]
            if extra is not None:
                found.append(best_gains(problem.blocks, inverse, open_ & extra, tries))
            tried = set()
            for candidate, gain in zip(*map(np.concatenate, zip(*found))):
                if int(candidate) not in tried:
                    tried.add(int(candidate))
                    trials.append(chosen[:position] + [int(candidate)] + chosen[position + 1 :])
                    information.append(base + gain)
        values = violations(trials)
        order = np.lexsort((-np.asarray(information), values))
        step = next((k for k in order if values[k] < now), None)
        if step is None:
            break
        now, chosen = float(values[step]), trials[step]
    return chosen


def compress(blocks: np.ndarray) -> np.ndarray:
    """Blocks with more rows than parameters replaced by p rows of the same information."""
    n, r, p = blocks.shape
    if r <= p:
        return blocks
    G = np.einsum("nrp,nrq->npq", blocks, blocks)
    w, V = np.linalg.eigh(G)
    return np.sqrt(np.clip(w, 0, None))[:, :, None] * V.transpose(0, 2, 1)
