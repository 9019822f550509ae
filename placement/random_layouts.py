"""Random layouts for the diagnosable search: drawn group by group, each candidate as likely as its kinematic
leverage, evaluated together, the admitted ones (or those nearest to diagnosable) kept as starts.

Where the walk towards diagnosable from the most informative layout stalls (a turned part, whose diagnosable
layouts need lines that add little information: the blocks for its axial rotation, a shaft's end faces for its
axial translation), diagnosable layouts can still be common enough to draw: on a 32-section cylinder 27 of 4 000
such 9 × 5 layouts are admitted, 5 of 4 000 drawn uniformly.
"""

from __future__ import annotations

import numpy as np

from massline.placement.candidates import CandidateLines

SAMPLES = 4000  # random layouts drawn, evaluated together, per budget of the diagnosable search


def drawn(rng: np.random.Generator, side: CandidateLines, budgets: tuple, weights: np.ndarray | None = None) -> list:
    """A random selection of ``side``'s candidates, ``budgets[g]`` of each group g, group by group, each as likely
    as its ``weights`` (None: all alike)."""
    chosen = []
    for g, k in enumerate(budgets):
        pool = np.flatnonzero(side.group == g)
        p = None if weights is None or not k else weights[pool] / weights[pool].sum()
        chosen += [int(i) for i in rng.choice(pool, k, replace=False, p=p)]
    return chosen


def line_leverages(side: CandidateLines, coords: np.ndarray) -> np.ndarray:
    """Each candidate's kinematic leverage among all of ``side``'s, Σ over its lines of cᵀ (CᵀC)⁻¹ c (C: every
    line's coordinates ``coords``): high where few candidates see its motion."""
    h = np.einsum("lq,qr,lr->l", coords, np.linalg.pinv(coords.T @ coords), coords)
    return np.append(h, 0.0)[side.members].sum(axis=1) + 1e-12


def sampled(planner, count: int, seed: int, keep: int) -> list[tuple[list, list]]:
    """The ``keep`` best of ``count`` random layouts (``seed``) of ``planner``'s (an :class:`.alternation.Planner`)
    budget groups: admitted ones when any is, else those nearest to diagnosable; evaluated together (``count``
    units of its work, fewer where less is left); a candidate as likely as its :func:`line_leverages`."""
    rng = np.random.default_rng(seed)
    sides = (
        (planner.s, planner.sensor_budgets, planner.s_coords),
        (planner.e, planner.exciter_budgets, planner.e_coords),
    )
    if any(np.sum(side.group == g) < k for side, budgets, _ in sides for g, k in enumerate(budgets)):
        return []
    weights = [line_leverages(side, coords) for side, _, coords in sides]
    left = max(planner.work.limit - planner.work.spent, 0)
    layouts = [
        tuple(drawn(rng, side, budgets, w) for (side, budgets, _), w in zip(sides, weights))
        for _ in range(min(count, left))
    ]
    violations = planner.violations(layouts)
    admitted = [c for c, v in zip(layouts, violations) if v == 0 and planner.admits(*c)]
    nearest = [layouts[k] for k in np.argsort(violations, kind="stable")]
    return (admitted or nearest)[:keep]
