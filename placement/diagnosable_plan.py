"""The default plan: the cheapest diagnosable layout, compared with the paper's minimal one.

The paper's minimal layout (6 sensor lines × 3 hits for a body, 3 × 3 for a plate) identifies
the body but cannot check itself: a faulty channel or hit is seen at best, never located
(:mod:`.diagnosability`). Budgets are tried from the cheapest that can be diagnosable
(q + 2 lines and 4 hits) upwards, fewest lines and hits first and, at equal count, fewest
accelerometers; the first budget whose optimal layout among the diagnosable ones exists and is at least as
accurate as the minimal plan (worst relative 1-σ) is planned and certified. D-optimality among diagnosable
layouts does not bound the worst 1-σ: a layout with more lines and hits than the paper's, that checks itself
but measures some parameter worse than the minimal one, is passed over for the next budget (the first
diagnosable one is the plan when none up to the last budget is as accurate). The minimal plan is kept beside
it, to state what diagnosability costs.

The search spends a budget of diagnosability evaluations (:mod:`.work`), shared by the budgets it tries: a
search that spends it stops, and the plan is then the first diagnosable layout it passed over, or with none the
minimal layout, with what the search reached.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Iterator

from massline.placement.certification import CERTIFY_STEPS
from massline.placement.candidates import CandidateOptions
from massline.placement.diagnosability import UndiagnosableError
from massline.core.errors import MasslineError, param
from massline.core.information import NoiseModel
from massline.core.lines import Lines
from massline.meshes.loader import BodyMesh
from massline.placement.on_surface import anchored, is_plate, plan
from massline.placement.planner import Budget, Plan
from massline.placement.work import Reached, Work, WorkSpent

MOST_EXTRA = 8  # lines and hits beyond the cheapest diagnosable budget tried before giving up
EVALUATIONS = 300_000  # diagnosability evaluations the search may spend (the bracket 59 945–80 483 on its 9 × 4, the
# structure 57 895–62 600 on its 9 × 4, by the BLAS kernel's rounding of tied trials: benchmarks/planned_bands.py)
UNIT = "diagnosability evaluations"


def minimal_budget(planar: bool) -> Budget:
    """The paper's minimal layout: 6 lines × 3 hits (18 masslines), a plate's 3 × 3 (9)."""
    return Budget(3 if planar else 6, 3)


def budgets(planar: bool, extra: int = MOST_EXTRA) -> Iterator[Budget]:
    """Uniaxial budgets that can be diagnosable, by lines + hits, then by fewest lines."""
    least = (3 if planar else 6) + 2
    for total in range(least + 4, least + 4 + extra + 1):
        for sensors in range(least, total - 4 + 1):
            yield Budget(sensors, total - sensors)


def cheapest_diagnosable(
    body: BodyMesh,
    options: CandidateOptions = CandidateOptions(),
    noise: NoiseModel = NoiseModel(),
    *,
    fixed_sensors: Lines | None = None,
    fixed_exciters: Lines | None = None,
    relaxation: str = "first-order",
    certify_steps: int = CERTIFY_STEPS,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
    evaluations: int = EVALUATIONS,
) -> Plan:
    """The diagnosable plan of fewest lines and hits by ``criterion``, certified, with the minimal plan as
    ``minimal`` and what the search spent as ``search``; the minimal plan, with what the search reached, when
    the search spends its ``evaluations`` first."""
    planar = is_plate(body)
    anchored(body, fixed_sensors, fixed_exciters, options)  # conflicting fixed lines refused before any work
    work = Work(evaluations, UNIT)

    def planned(budget: Budget, diagnosable: bool, steps: int) -> Plan:
        return plan(
            body, budget, options, noise, fixed_sensors=fixed_sensors, fixed_exciters=fixed_exciters,
            relaxation=relaxation, planar=planar, certify_steps=steps, criterion=criterion,
            diagnosable=diagnosable, work=work,
        )  # fmt: skip

    progress("the minimal layout", 0.0)
    minimal = planned(minimal_budget(planar), False, 0)
    tried, coarser = [], []
    for budget in budgets(planar):
        progress(f"a diagnosable layout of {_size(budget)} ({work.spent} of {work.limit} {UNIT} spent)", work.fraction)
        try:
            found = planned(budget, True, certify_steps)
        except UndiagnosableError:
            tried.append(budget)
            continue
        except WorkSpent:
            if coarser:
                return _first_diagnosable(coarser, minimal, work, stopped=True)
            return replace(minimal, search=_reached(work, True, _stopped_phrase(tried, budget)))
        if found.worst_relative_std > minimal.worst_relative_std:
            coarser.append(found)
            continue
        what = f"a diagnosable layout of {_size(budget)}, after {len(tried)} smaller budgets with none"
        if coarser:
            what += f" and {len(coarser)} with one less accurate than the minimal plan ({_less_accurate(coarser)})"
        return replace(found, minimal=minimal, search=_reached(work, False, what))
    if coarser:
        return _first_diagnosable(coarser, minimal, work, stopped=False)
    raise MasslineError(
        f"no diagnosable layout of up to {budget.sensors + budget.exciters} lines and hits was found: "
        f"give the budget ({param('budget.sensors')}, {param('budget.exciters')}) or plan the minimal layout "
        f"({param('minimal_budget')})"
    )


def _first_diagnosable(coarser: list[Plan], minimal: Plan, work: Work, stopped: bool) -> Plan:
    """The first diagnosable plan found, though less accurate than the minimal one: none that is as accurate was
    found up to the last budget, or before the search's budget ended (``stopped``)."""
    first = coarser[0]
    what = (
        f"a diagnosable layout of {_shape(first)}, less accurate than the minimal plan: none as accurate "
        f"{'before the budget ended' if stopped else 'up to the last budget'} ({_less_accurate(coarser)})"
    )
    return replace(first, minimal=minimal, search=_reached(work, stopped, what))


def _less_accurate(plans: list[Plan]) -> str:
    """``8 lines × 4 hits at 1.73 %, …``: the diagnosable layouts passed over and their worst relative 1-σ."""
    return ", ".join(f"{_shape(p)} at {p.worst_relative_std:.2%}" for p in plans)


def _shape(plan: Plan) -> str:
    return f"{len(plan.sensors)} lines × {len(plan.exciters)} hits"


def _size(budget: Budget) -> str:
    return f"{budget.sensors} lines × {budget.exciters} hits"


def _reached(work: Work, stopped: bool, what: str) -> Reached:
    return Reached(min(work.spent, work.limit), work.limit, work.unit, stopped, what)


def _stopped_phrase(tried: list, searching: Budget) -> str:
    """What a stopped search reached: the budgets it closed without a diagnosable layout, the one it was in."""
    closed = (
        f"{len(tried)} budgets ({_size(tried[0])} to {_size(tried[-1])}) without a diagnosable layout"
        if tried
        else "no budget closed"
    )
    return f"{closed}, stopped within {_size(searching)}; planned the minimal layout, not diagnosable"
