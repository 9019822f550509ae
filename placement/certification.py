"""Certification of a planned layout: each side's upper bound with the other side held at the layout.

A side's bound covers every selection of that side with the other side fixed (certificate.py for log det F,
criterion_relaxation.py for A and E), so the efficiency stated is against the best layout that changes the
sensors alone or the exciters alone. ``planner`` is a :class:`.planner.Planner` (its side problems,
admissibility and covers).
"""

from __future__ import annotations

import time

from massline.placement.certificate import TARGETS, certify
from massline.placement.criterion_relaxation import relax_criterion


def certify_sides(planner, sensors: list, exciters: list, relaxation: str, seconds: float, targets):
    """Both sides' D bounds at the layout, and the layouts better on one side that the search met."""
    deadline = time.perf_counter() + seconds
    sp = planner.sensor_problem(planner.exciter_rows(exciters))
    ep = planner.exciter_problem(planner.sensor_rows(sensors))
    U_s, better_s = certify(
        sp,
        sensors,
        relaxation,
        lambda c: planner.admits(c, exciters),
        planner.sensor_cover(exciters),
        seconds / 2,
        targets,
    )
    remaining = max(deadline - time.perf_counter(), 0.0)
    U_e, better_e = certify(
        ep, exciters, relaxation, lambda c: planner.admits(sensors, c), planner.exciter_cover, remaining, targets
    )
    value = ep.value(exciters)
    improved = [(sp.value(better_s), better_s, exciters), (ep.value(better_e), sensors, better_e)]
    return {"sensors": U_s, "exciters": U_e}, [
        c for c in improved if c[0] > value + 1e-9 and planner.admits(c[1], c[2])
    ]


def certify_d(planner, sensors: list, exciters: list, relaxation: str, seconds: float):
    """Both sides' D bounds (certificate.py). At the first target a better layout the search meets
    is adopted and both sides certified anew (up to three times); the time left tightens the
    bounds of the final layout towards the last target. Returns the sensors, exciters and bounds."""
    deadline = time.perf_counter() + seconds
    for _ in range(3):
        remaining = max(deadline - time.perf_counter(), 0.0)
        bounds, improved = certify_sides(planner, sensors, exciters, relaxation, remaining, TARGETS[:1])
        if not improved or time.perf_counter() > deadline:
            break
        _, sensors, exciters = max(improved, key=lambda c: c[0])
    if not improved and time.perf_counter() < deadline:
        remaining = deadline - time.perf_counter()
        tighter = certify_sides(planner, sensors, exciters, relaxation, remaining, TARGETS[1:])[0]
        bounds = {side: min(bounds[side], tighter[side]) for side in bounds}
    return sensors, exciters, bounds


def certify_criterion(planner, sensors: list, exciters: list) -> dict:
    """Both sides' bounds of an A or E plan (criterion_relaxation.py)."""
    return {
        "sensors": relax_criterion(planner.sensor_problem(planner.exciter_rows(exciters)), planner.criterion, sensors),
        "exciters": relax_criterion(planner.exciter_problem(planner.sensor_rows(sensors)), planner.criterion, exciters),
    }
