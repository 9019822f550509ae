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
side's bound stays valid for it, and only the other side is certified anew. Time goes
to the side of the larger bound, since that one sets the certified efficiency: neither
side's branch and bound starts again from its root when the other side's is run.

The efficiency a plan states is the certificate's own, the criterion's efficiency against the larger bound
(:func:`certified_efficiency`). A bound is at or above the layout it certifies, so that efficiency is at most 1;
one above 1 (beyond rounding) is a bound below the layout, a wrong certificate: raised, never clipped to 100 %.
"""

from __future__ import annotations

from massline.placement.certificate import SideBound
from massline.placement.criteria import Criterion
from massline.placement.criterion_relaxation import relax_criterion
from massline.placement.work import STEPS, Work

SIDES = ("sensors", "exciters")
ROUNDING = 1e-9  # an efficiency this far above 1 is a bound equal to the layout's value, up to float rounding


class CertificateError(AssertionError):
    """An internal error: a certificate whose bound is below the layout it certifies (an efficiency above 1)."""


def certified_efficiency(criterion: Criterion, value: float, bounds: dict, p: int) -> float:
    """The efficiency the certificate states for a layout: a lower bound of it against every one-side change.

    Parameters
    ----------
    criterion : Criterion
        The plan's criterion (D, A or E), whose ``efficiency`` is taken.
    value : float
        The layout's criterion value (of the scaled information: log det F for D).
    bounds : dict
        Each side's upper bound U of the criterion ("sensors", "exciters"), in ``value``'s units.
    p : int
        Parameters of the model (10, or 6 for a plate).

    Returns
    -------
    float
        The criterion's efficiency against the larger bound (D: exp((value − U)/p)), dimensionless; 1 when it
        exceeds 1 by rounding alone (ROUNDING).

    Raises
    ------
    CertificateError
        Above 1 + ROUNDING: a bound below the layout itself, which no true bound is.
    """
    efficiency = criterion.efficiency(value, max(bounds.values()), p)
    if efficiency > 1 + ROUNDING:
        raise CertificateError(
            f"the {criterion.name} certificate states an efficiency of {efficiency:.9g} > 1: its bound "
            f"{max(bounds.values()):.9g} is below the layout's own {criterion.title} {value:.9g}"
        )
    return min(efficiency, 1.0)


class _Sides:
    """One side's selection problem with the other side held (the planner keeps the last one built per side)."""

    def __init__(self, planner):
        self.planner = planner

    def problem(self, side: str, layout: dict):
        p, other = self.planner, layout[_other(side)]
        if side == "sensors":
            return p.sensor_problem(p.exciter_rows(other), other)
        return p.exciter_problem(p.sensor_rows(other), other)

    def admissible(self, side: str, layout: dict):
        other = layout[_other(side)]
        if side == "sensors":
            return lambda chosen: self.planner.admits(chosen, other)
        return lambda chosen: self.planner.admits(other, chosen)

    def cover(self, side: str, layout: dict):
        return self.planner.sensor_cover(layout["exciters"]) if side == "sensors" else self.planner.exciter_cover

    def bound(self, side: str, layout: dict, relaxation: str, work: Work) -> SideBound:
        """The side's bound at the layout, the other side held: its relaxation solved, ready to tighten on
        ``work``."""
        problem, admissible = self.problem(side, layout), self.admissible(side, layout)
        cover = self.cover(side, layout)
        return SideBound(problem, layout[side], relaxation, admissible=admissible, cover_for=cover, work=work)


def _other(side: str) -> str:
    return SIDES[1 - SIDES.index(side)]


SLICE = 500  # relaxation steps the branch and bound of one side takes before the sides are compared again
CERTIFY_STEPS = 30_000  # the D certificate's default budget (relaxation steps): at most ~12 s on 2 cores (2 500 a second)


def certify_d(planner, sensors: list, exciters: list, relaxation: str, steps: int) -> tuple[list, list, dict, Work]:
    """The layout, improved where a side's branch and bound met better, its bounds U_s, U_e, and the work spent.

    ``planner`` is the placement.planner.Planner over every candidate. Each side's relaxation
    bounds it first; for ``steps`` relaxation steps then, the side whose bound is the larger (the one
    that sets the certified efficiency) is tightened by its branch and bound, a slice at a time,
    until that side can close no further. A better selection met on one side is adopted and
    the other side's bound computed anew (module docstring); when the steps run out before that
    bound is as tight as the one given up, the layout before is returned with its bounds
    (the one of greater certified efficiency, both bounds valid for it). A budget of work, not of
    seconds: the certificate a plan states is the same on any machine.
    """
    work = Work(steps, STEPS)
    sides, layout = _Sides(planner), {"sensors": list(sensors), "exciters": list(exciters)}
    bounds = {side: sides.bound(side, layout, relaxation, work) for side in SIDES}

    def certified() -> tuple:
        value = sides.problem(SIDES[0], layout).value(layout[SIDES[0]])
        stated = {side: float(bounds[side].bound) for side in SIDES}
        return value - max(stated.values()), layout["sensors"], layout["exciters"], stated

    before = []
    while not work.reached():
        side = max(SIDES, key=lambda s: bounds[s].bound)
        if bounds[side].finished:
            break
        bounds[side].tighten(min(work.limit, work.spent + SLICE), work.limit)
        problem = sides.problem(side, layout)
        if problem.value(bounds[side].best) > problem.value(layout[side]) + 1e-9:
            before.append(certified())
            layout = {**layout, side: bounds[side].best}
            bounds[_other(side)] = sides.bound(_other(side), layout, relaxation, work)
    return *max([certified()] + before, key=lambda c: c[0])[1:], work


def certify_criterion(planner, sensors: list, exciters: list) -> dict:
    """Both sides' bounds of an A or E plan (criterion_relaxation.py), each with the other side held."""
    layout = {"sensors": sensors, "exciters": exciters}
    sides = _Sides(planner)
    return {side: relax_criterion(sides.problem(side, layout), planner.criterion, layout[side]) for side in SIDES}
