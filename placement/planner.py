"""The pre-test planner: the sensor and exciter layout of greatest information.

    maximise over S, E   φ(F(S, E)),   F = Σ_{i∈S, j∈E} g_ij g_ijᵀ / σ_ij²,

φ = log det (D, the default), −tr(·)⁻¹ (A) or λ_min (E) of the scaled
information (criteria.py).

F is linear in the sensors for fixed exciters and vice versa, so the layout is
found by alternating the two selection problems (greedy, then exchanges), from
several starts, until neither side improves. Each side's convex relaxation
bounds from above the best layout that changes that side alone, the other held
(certification.py); the plan states the certified efficiency of the worse side in
the criterion's sense (D: exp((log det F − U)/p)): a lower bound against every
layout that changes the sensors alone or the exciters alone, not both at once. A and E
start from the D layout and climb their own criterion from there. Only layouts that the paper's
equations can solve, with a well-posed kinematic step and one accelerometer per point, are admitted
(:mod:`.admissible`: rank S = 6, non-singular dynamic systems, κ(S̃) bounded), and, when asked, only
diagnosable ones (:mod:`.diagnosability`): an inadmissible selection is first walked by single exchanges
to one that is. On a mesh (:func:`.on_surface.plan`) the chosen points then slide off the candidate
grid on their flat faces and along curves (:mod:`.sliding`), which raises the criterion beyond the certified layout.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from massline.placement.alternation import BLOCKS, EVALUATIONS, WORKING_SET, Planner, PlannerSettings
from massline.placement.candidates import BLOCK, CandidateLines
from massline.placement.certification import CERTIFY_STEPS, certify_criterion, certify_d
from massline.placement.criteria import CRITERIA, D
from massline.placement.diagnosability import UndiagnosableError
from massline.placement.footprints import Footprints
from massline.core.errors import MasslineError, param
from massline.core.information import NoiseModel
from massline.placement.plans import Budget, Plan, assessed, fixed_nodes
from massline.placement.random_layouts import SAMPLES, sampled
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.placement.work import Reached, Work

MORE_BLOCKS = 2  # block lines and hits beyond the least the motion needs, tried when no layout is found

__all__ = [  # the planner's vocabulary, from here as from the modules that define it
    "WORKING_SET", "Budget", "CandidateLines", "Found", "Planner", "PlannerSettings",
    "certified", "check_candidates", "plan_on_candidates", "polished", "searched",
]  # fmt: skip


@dataclass(frozen=True, kw_only=True)
class Found:
    """A search's layout: sensor and exciter candidate indices, its criterion value, and whether the planner
    admits it."""

    sensors: list
    exciters: list
    value: float
    admitted: bool


def _search(searcher: Planner, starts: list, progress) -> Found:
    """The best alternation over the starts (exciter sets), by the searcher's criterion: an admitted layout
    before any other, then the greater value."""
    best = None
    for k, start in enumerate(starts):
        progress("alternating sensors and exciters", 0.8 * k / len(starts))
        sensors, exciters, value = searcher.alternate(*start)
        admitted = searcher.admits(sensors, exciters)
        if best is None or (admitted, value) > (best.admitted, best.value):
            best = Found(sensors=sensors, exciters=exciters, value=value, admitted=admitted)
    return best


def polished(planner: Planner, sensors: list, exciters: list) -> tuple[list, list]:
    """The working sets' layout carried on by exchanges among every candidate, each side in turn, staying
    admitted: the working sets hold a few thousand lines, and the best admitted layout of 1e5 may lie
    between them (a sensor a few millimetres from a working-set point)."""
    s, e, _ = planner.alternate(exciters, sensors)
    return (s, e) if planner.admits(s, e) else (sensors, exciters)


def check_candidates(sensor_side: CandidateLines, exciter_side: CandidateLines, budget: Budget) -> None:
    """Refuse candidates fewer than the budget on either side."""
    sides = (
        ("sensor", sensor_side, budget.sensors, param("options.sensor_base")),
        ("exciter", exciter_side, budget.exciters, param("options.hammer_tip")),
    )
    for name, side, need, option in sides:
        if len(side) < need:
            raise MasslineError(
                f"only {len(side)} {name} candidates for a budget of {need}: sample more points "
                f"({param('options.n_samples')}), relax the exclusions or give a smaller {option} "
                "(places clear of sharp edges, flat or curved gently enough, are few)"
            )


def searched(settings: PlannerSettings, planner: Planner, starts: int, seed: int, progress) -> tuple[list, list]:
    """The layout (candidate indices) the search finds on the working sets of ``planner`` (the settings' by D,
    over every candidate), carried on among every candidate when the working sets hold fewer: by D, then
    (A, E) by the settings' criterion from there. Where diagnosability is asked, the alternation starts from
    the most informative exciters and from the random layouts nearest to diagnosable
    (:func:`.random_layouts.sampled`: the diagnosable ones where any was drawn), not from random exciters: the
    walk towards diagnosable from the most informative layout stalls on a turned part, whose diagnosable layouts
    need lines that add little information (the blocks, the end faces)."""
    d_settings, sides = replace(settings, criterion=D), (planner.s, planner.e)
    s_work, e_work = planner.working_sets(seed)
    subsets = sides[0].subset(s_work), sides[1].subset(e_work)
    searcher = d_settings.planner(*subsets)
    drawn = sampled(searcher, SAMPLES, seed, starts - 1) if settings.diagnosable else []
    begin = [(start,) for start in searcher.starts(0 if drawn else starts - 1, seed)] + [(e, s) for s, e in drawn]
    best = _search(searcher, begin, progress)
    if settings.criterion is not D:
        best = _search(settings.planner(*subsets), [(best.exciters, best.sensors)], progress)
    if settings.diagnosable and not best.admitted:
        raise UndiagnosableError(f"no diagnosable layout of {settings.budget} was found among the candidates")
    if not best.admitted:
        raise MasslineError(
            "the candidates and keep-outs leave only degenerate or ill-conditioned layouts: allow points that are "
            "not all in one line or plane, and hits in several directions (relax the exclusions, "
            f"{param('options.sensor_base')} or {param('options.hammer_tip')})"
        )
    sensors, exciters = [int(i) for i in s_work[best.sensors]], [int(i) for i in e_work[best.exciters]]
    if len(s_work) < len(sides[0]) or len(e_work) < len(sides[1]):
        progress("exchanging on every candidate", 0.82)
        polisher = planner if settings.criterion is D else settings.planner(*sides)
        sensors, exciters = polished(polisher, sensors, exciters)
    return sensors, exciters


def with_blocks(
    settings: PlannerSettings, sensor_side: CandidateLines, exciter_side: CandidateLines, starts: int, seed: int,
    progress,
) -> tuple[PlannerSettings, Planner, tuple[list, list]]:
    """The settings, D planner and searched layout with as few lines and hits on mounting blocks as give a
    well-posed one (``alternation.BLOCKS``, then up to ``MORE_BLOCKS`` more of each where the candidates have
    blocks: the idler riser's one block line leaves its kinematics ill-conditioned); a budget with no diagnosable
    layout is refused as it is (the diagnosable search tries the next budget)."""
    least = BLOCKS[settings.diagnosable]

    def with_more(more: int) -> tuple[PlannerSettings, Planner]:
        tried = replace(settings, blocks=(least[0] + more, least[1] + more))
        return tried, replace(tried, criterion=D).planner(sensor_side, exciter_side)

    tried, planner = with_more(0)
    planner.check_directions()
    has_blocks = bool(np.any(sensor_side.group == BLOCK) or np.any(exciter_side.group == BLOCK))
    for more in range(1, MORE_BLOCKS + 1 if has_blocks else 1):
        try:
            return tried, planner, searched(tried, planner, starts, seed, progress)
        except UndiagnosableError:  # no diagnosable layout of this budget: the next budget's to find, not more blocks
            raise
        except MasslineError:  # no well-posed layout at all
            tried, planner = with_more(more)
    return tried, planner, searched(tried, planner, starts, seed, progress)


def certified(
    settings: PlannerSettings, planner: Planner, layout: tuple[list, list], relaxation: str, steps: int
) -> tuple[list, list, dict, dict, Reached]:
    """The layout (improved where the D certificate's branch and bound met better), the bounds of its criterion
    and those of log det F (``certification``), and what the D certificate spent of its ``steps``: an A or E
    layout's bounds are its criterion's, over every layout (diagnosable or not)."""
    if settings.criterion is D:
        sensors, exciters, d_bounds, work = certify_d(planner, *layout, relaxation, steps)
        return sensors, exciters, d_bounds, d_bounds, spent(work)
    *_, d_bounds, work = certify_d(planner, *layout, relaxation, 0)
    everyone = replace(settings, diagnosable=False).planner(planner.s, planner.e)
    return *layout, certify_criterion(everyone, *layout), d_bounds, spent(work)


def spent(work: Work) -> Reached:
    """What the D certificate spent: stopped when its budget ended it before it could close no further."""
    return Reached(work.spent, work.limit, work.unit, work.reached(), "the bounds stated")


def plan_on_candidates(
    model: RigidModel,
    sensor_side: CandidateLines,
    exciter_side: CandidateLines,
    budget: Budget,
    noise: NoiseModel = NoiseModel(),
    *,
    fixed_sensors: Lines | None = None,
    fixed_exciters: Lines | None = None,
    relaxation: str = "first-order",
    starts: int = 3,
    seed: int = 0,
    certify_steps: int = CERTIFY_STEPS,
    progress: Callable[[str, float], None] = lambda stage, fraction: None,
    criterion: str = "D",
    diagnosable: bool = False,
    work: Work | None = None,
    footprints: Footprints | None = None,
) -> Plan:
    """The best layout of ``budget`` among given candidate lines, certified, with predicted 1-σ.

    ``certify_steps`` bounds the branch and bound that tightens the D certificate (relaxation steps, a budget of
    work, not of seconds); what it reaches by then is what the plan states. ``criterion`` is "D", "A" or "E"
    (criteria.py): A and E alternate from the D layout by their own criterion. ``diagnosable``: only
    layouts in which one faulty channel or hit can be located are admitted (the certificate's bound covers
    all layouts). ``starts``: the alternation starts from the greedy exciters and ``starts`` − 1 random
    sets (``seed``). ``work``: the diagnosability evaluations the search may spend (:mod:`.work`; it raises
    ``WorkSpent`` past them). ``footprints``: hits kept off the accelerometers' footprints and accelerometers
    a base apart (:mod:`.footprints`; the nodes of the candidate lines index its candidates).
    """
    budget.check(model.planar)
    check_candidates(sensor_side, exciter_side, budget)
    settings = PlannerSettings(
        model=model,
        budget=budget,
        noise=noise,
        fixed_sensors=fixed_sensors,
        fixed_exciters=fixed_exciters,
        criterion=CRITERIA[criterion],
        diagnosable=diagnosable,
        work=work,
        footprints=footprints,
    )
    settings, planner, layout = with_blocks(settings, sensor_side, exciter_side, starts, seed, progress)
    planner.work = Work(EVALUATIONS, planner.work.unit)  # the certificate's checks: bounded by its steps instead
    progress("certifying", 0.85)
    sensors, exciters, bounds, d_bounds, certificate = certified(settings, planner, layout, relaxation, certify_steps)
    S_all, E_all = planner.layout(sensors, exciters)
    assessment = assessed(model, S_all, E_all, noise)
    return Plan(
        model=model,
        sensors=S_all,
        sensor_nodes=fixed_nodes(fixed_sensors, sensor_side.node[sensor_side.line_index(sensors)]),
        exciters=E_all,
        exciter_nodes=fixed_nodes(fixed_exciters, exciter_side.node[exciter_side.line_index(exciters)]),
        bounds=bounds,
        noise=noise,
        n_candidate_lines={"sensors": len(sensor_side.lines), "exciters": len(exciter_side.lines)},
        criterion=settings.criterion,
        value=settings.criterion.value(assessment["information"]),
        d_bounds=d_bounds,
        certificate=certificate,
        candidate_log_det=assessment["log_det"],
        **assessment,
    )
