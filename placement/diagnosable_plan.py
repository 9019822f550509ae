"""The default plan: the cheapest diagnosable layout, compared with the paper's minimal one.

The paper's minimal layout (6 sensor lines × 3 hits for a body, 3 × 3 for a plate) identifies
the body but cannot check itself: a faulty channel or hit is seen at best, never located
(:mod:`.diagnosability`). Budgets are tried from the cheapest that can be diagnosable
(q + 2 lines and 4 hits) upwards, fewest lines and hits first and, at equal count, fewest
accelerometers; the first budget whose optimal layout among the diagnosable ones exists is
planned and certified. The minimal plan is kept beside it, to state what diagnosability costs.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable, Iterator

from massline.placement.candidates import CandidateOptions
from massline.placement.diagnosability import UndiagnosableError
from massline.core.errors import MasslineError, param
from massline.core.information import NoiseModel
from massline.core.lines import Lines
from massline.meshes.loader import BodyMesh
from massline.placement.on_surface import is_plate, plan
from massline.placement.planner import Budget, Plan

MOST_EXTRA = 8  # lines and hits beyond the cheapest diagnosable budget tried before giving up


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
    certify_seconds: float = 20.0,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
) -> Plan:
    """The diagnosable plan of fewest lines and hits by ``criterion``, certified, with the minimal plan as
    ``minimal``."""
    planar = is_plate(body)

    def planned(budget: Budget, diagnosable: bool, seconds: float) -> Plan:
        return plan(
            body, budget, options, noise, fixed_sensors=fixed_sensors, fixed_exciters=fixed_exciters,
            relaxation=relaxation, planar=planar, certify_seconds=seconds, criterion=criterion,
            diagnosable=diagnosable,
        )  # fmt: skip

    progress("the minimal layout", 0.0)
    minimal = planned(minimal_budget(planar), False, 0.0)
    for budget in budgets(planar):
        progress(f"a diagnosable layout of {budget.sensors} lines × {budget.exciters} hits", 0.1)
        try:
            return replace(planned(budget, True, certify_seconds), minimal=minimal)
        except UndiagnosableError:
            continue
    raise MasslineError(
        f"no diagnosable layout of up to {budget.sensors + budget.exciters} lines and hits was found: "
        f"give the budget ({param('budget.sensors')}, {param('budget.exciters')}) or plan the minimal layout "
        f"({param('minimal_budget')})"
    )
