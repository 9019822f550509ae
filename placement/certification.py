"""Certifying a planned layout: an upper bound of each side's problem, the other side held.

What is certified. For the plan's layout (S, E) two numbers are computed,

    U_s ≥ max over admissible sensor selections S′ within the budget of log det F(S′, E),
    U_e ≥ max over admissible exciter selections E′ within the budget of log det F(S, E′),

each from that side's relaxation tightened by branch and bound and admissibility cuts
(certificate.py), every one a true upper bound. The plan's certified D-efficiency

    exp((log det F(S, E) − max(U_s, U_e)) / p)

is therefore a lower bound of its efficiency against every layout that changes the
sensors alone or the exciters alone: no such change can gain more. It is not a bound
against layouts that change both sides at once: F is bilinear in the two selections,
the joint problem has no concave relaxation of this kind, and none is claimed.

Each side's bound depends only on the other side (U_s only on E). So when one side's
branch and bound meets a better selection of that side, the selection is adopted, the
side's bound stays valid for it, and only the other side is certified anew. The sensor
side (cheap) is certified first, so that the costly exciter side is certified once, at
the final sensors, in the usual case.
"""

from __future__ import annotations

import time

import numpy as np

from massline.placement.certificate import TARGETS, certify
from massline.placement.criterion_relaxation import relax_criterion

SIDES = ("sensors", "exciters")


class _Sides:
    """One side's selection problem with the other side held, built once per held selection."""

    def __init__(self, planner):
        self.planner, self.built = planner, {}

    def problem(self, side: str, layout: dict):
        other = layout[_other(side)]
        key = (side, tuple(other))
        if key not in self.built:
            p = self.planner
            held = p.exciter_rows(other) if side == "sensors" else p.sensor_rows(other)
            self.built[key] = p.sensor_problem(held) if side == "sensors" else p.exciter_problem(held)
        return self.built[key]

    def admissible(self, side: str, layout: dict):
        other = layout[_other(side)]
        if side == "sensors":
            return lambda chosen: self.planner.admits(chosen, other)
        return lambda chosen: self.planner.admits(other, chosen)

    def cover(self, side: str, layout: dict):
        return self.planner.sensor_cover(layout["exciters"]) if side == "sensors" else self.planner.exciter_cover


def _other(side: str) -> str:
    return SIDES[1 - SIDES.index(side)]


def _certify_side(sides: _Sides, side: str, layout: dict, relaxation: str, seconds: float, targets) -> tuple:
    """U of one side at the layout, and the best admissible selection of that side met."""
    problem, admissible = sides.problem(side, layout), sides.admissible(side, layout)
    bound, best = certify(problem, layout[side], relaxation, admissible, sides.cover(side, layout), seconds, targets)
    better = problem.value(best) > problem.value(layout[side]) + 1e-9 and admissible(best)
    return bound, best if better else layout[side]


def certify_d(planner, sensors: list, exciters: list, relaxation: str, seconds: float) -> tuple[list, list, dict]:
    """The layout, improved where a side's branch and bound met better, and its bounds U_s, U_e.

    ``planner`` is the placement.planner.Planner over every candidate. Sides are certified
    to the first target in turn; a better selection met on one side is adopted and the
    other side's bound dropped, to be computed again (module docstring). Each call gets
    an even share of the time left among the sides still to certify; after ``seconds``
    the relaxation's bound alone is computed. Time left then tightens both bounds towards
    the last target. Every bound met is valid for the final layout: the least is kept.
    """
    deadline = time.perf_counter() + seconds
    sides, layout, bounds = _Sides(planner), {"sensors": list(sensors), "exciters": list(exciters)}, {}
    while len(bounds) < len(SIDES):
        side = next(s for s in SIDES if s not in bounds)
        share = max(deadline - time.perf_counter(), 0.0) / (len(SIDES) - len(bounds))
        bounds[side], chosen = _certify_side(sides, side, layout, relaxation, share, TARGETS[:1])
        if chosen != layout[side]:
            layout[side] = chosen
            bounds.pop(_other(side), None)
    for k, side in enumerate(SIDES):
        share = max(deadline - time.perf_counter(), 0.0) / (len(SIDES) - k)
        gap = bounds[side] - sides.problem(side, layout).value(layout[side])
        if share > 0 and gap > planner.model.p * np.log(1 / TARGETS[-1]):
            tighter = _certify_side(sides, side, layout, relaxation, share, TARGETS[1:])[0]
            bounds[side] = min(bounds[side], tighter)
    return layout["sensors"], layout["exciters"], {side: float(bounds[side]) for side in SIDES}


def certify_criterion(planner, sensors: list, exciters: list) -> dict:
    """Both sides' bounds of an A or E plan (criterion_relaxation.py), each with the other side held."""
    layout = {"sensors": sensors, "exciters": exciters}
    sides = _Sides(planner)
    return {side: relax_criterion(sides.problem(side, layout), planner.criterion, layout[side]) for side in SIDES}
