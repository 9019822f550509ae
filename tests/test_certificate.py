"""The D certificate: a resumable branch and bound, closing against admissible selections, at 1e5 lines."""

import itertools

import numpy as np
import pytest
import trimesh
from conftest import bundled

from massline.core import Lines
from massline.placement.admissible import KINEMATIC_LIMIT, kinematic_condition
from massline.placement.cell_bound import BranchAndBound
from massline.placement.certificate import SideBound
from massline.placement.certification import certify_d
from massline.core.information import NoiseModel
from massline.core.model import RigidModel
from massline.placement.planner import WORKING_SET, Budget, CandidateLines, Planner, plan_on_candidates, polished


def _planner(n: int, seed: int = 1) -> tuple[Planner, CandidateLines]:
    """n candidate lines (surface normals) sampled on the bundled structure, one set for both sides."""
    body = bundled("structure")
    points, faces = trimesh.sample.sample_surface(body.mesh, n, seed=seed)
    side = CandidateLines.single(Lines(points, body.mesh.face_normals[faces]))
    return Planner(RigidModel(body.nominal), side, side, Budget(6, 3), NoiseModel()), side


def _admitted_layout(planner: Planner, among: int) -> tuple[list, list]:
    """An admitted layout searched among the first ``among`` candidates only (same indices)."""
    first = np.arange(among)
    local = Planner(planner.model, planner.s.subset(first), planner.e.subset(first), planner.budget, planner.noise)
    sensors, exciters, _ = local.alternate(local.starts(0, seed=0)[0])
    assert local.admits(sensors, exciters)
    return sensors, exciters


def _gap(planner: Planner, sensors: list, exciters: list, bounds: dict) -> float:
    value = planner.sensor_problem(planner.exciter_rows(exciters)).value(sensors)
    return value - max(bounds.values())


def test_branch_and_bound_paused_and_resumed_is_the_search_run_at_once():
    planner, _ = _planner(400)
    sensors, exciters = _admitted_layout(planner, 400)
    problem = planner.sensor_problem(planner.exciter_rows(exciters))
    slack = problem.p * np.log(1 / 0.999)
    at_once = BranchAndBound(problem, sensors, slack)
    at_once.run(np.inf, max_nodes=24)
    in_pieces = BranchAndBound(problem, sensors, slack)
    for nodes in range(4, 25, 4):
        in_pieces.run(np.inf, max_nodes=nodes)
    assert at_once.nodes == in_pieces.nodes == 24
    assert in_pieces.bound == pytest.approx(at_once.bound, rel=1e-12)
    assert in_pieces.best == at_once.best


def test_only_admissible_selections_become_the_best_and_the_bound_still_covers_all():
    """12 sensor candidates, 6 to choose: the optimum declared inadmissible stays out of ``best``, the
    bound still covers it (brute force), and the branch and bound goes on past it."""
    planner, _ = _planner(21, seed=0)
    problem = planner.sensor_problem(planner.exciter_rows([12, 13, 14]))
    problem = type(problem)(problem.blocks[:12], problem.group[:12], problem.budgets, problem.fixed)
    values = {c: problem.value(list(c)) for c in itertools.combinations(range(12), 6)}
    optimum = max(values, key=values.get)
    admissible = lambda chosen: sorted(chosen) != list(optimum)  # noqa: E731
    start = sorted(values, key=values.get)[-2]
    search = BranchAndBound(problem, list(start), slack=1e-6, admissible=admissible)
    search.run(np.inf)
    assert search.finished
    assert tuple(search.best) != optimum and admissible(search.best)
    assert search.best_value == pytest.approx(values[start])
    assert search.bound >= values[optimum] - 1e-9


def test_certify_d_never_states_less_than_its_relaxation_nor_a_wrong_bound():
    """Whatever the budget, the stated gap is at least the relaxation's at the given layout (a better selection
    adopted late never costs the certificate), and each side's bound covers every change of that side; the work
    spent stays within the budget, but for the relaxation steps of the node running when it ran out."""
    planner, _ = _planner(3000)
    sensors, exciters = _admitted_layout(planner, 300)
    relaxation = _gap(planner, sensors, exciters, certify_d(planner, sensors, exciters, "first-order", 0)[2])
    for steps in (100, 800, 2500):
        s, e, bounds, work = certify_d(planner, sensors, exciters, "first-order", steps)
        assert planner.admits(s, e) and work.spent <= steps + 25  # the relaxation looks every 25 steps
        assert _gap(planner, s, e, bounds) >= relaxation - 1e-9, steps


def test_side_bound_ends_within_its_last_target_or_at_a_better_inadmissible_selection():
    """Run to its end, a side's bound is within 1 % (D-efficiency) of the best admissible selection, or of an
    inadmissible one it met (no bound can fall below that one's value): the bound covers every selection."""
    planner, _ = _planner(3000)
    sensors, exciters = _admitted_layout(planner, 300)
    problem = planner.sensor_problem(planner.exciter_rows(exciters))
    admissible = lambda chosen: planner.admits(chosen, exciters)  # noqa: E731
    side = SideBound(problem, sensors, admissible=admissible)
    side.tighten(np.inf)
    assert side.finished
    assert admissible(side.best) and problem.value(side.best) >= problem.value(sensors)
    slack = problem.p * np.log(1 / 0.99)
    if side.bound > problem.value(side.best) + slack + 1e-9:
        value, met = side.search.best_any
        assert not admissible(met) and side.bound <= value + slack + 1e-9, (side.bound, value)


def test_exchanges_on_every_candidate_carry_the_working_sets_layout_on():
    planner, _ = _planner(3 * WORKING_SET)
    sensors, exciters = _admitted_layout(planner, WORKING_SET // 4)
    s, e = polished(planner, sensors, exciters)
    before = planner.sensor_problem(planner.exciter_rows(exciters)).value(sensors)
    after = planner.sensor_problem(planner.exciter_rows(e)).value(s)
    assert planner.admits(s, e)
    assert after > before + 0.05, (before, after)


@pytest.mark.long  # the certificate at scale (half a minute); the small planners above check its arithmetic
def test_minimal_plan_on_1e5_lines_is_certified_within_95_percent():
    """A large body's scale: 1e5 candidate lines, the paper's 6 × 3. Time is measured in benchmarks/plan_scaling.py
    (about 4 s on 2 cores); here the branch and bound is given room for a slower machine."""
    planner, side = _planner(100_000)
    plan = plan_on_candidates(planner.model, side, side, Budget(6, 3), certify_steps=25000)
    assert plan.d_efficiency_lower_bound >= 0.95
    assert kinematic_condition(planner.model, plan.sensors) <= KINEMATIC_LIMIT


def test_the_certificate_is_the_same_whatever_the_machine():
    """A budget of relaxation steps, not seconds: two runs state the same bounds and layout, to the bit, however
    long each took (with seconds, a slower machine stated 94.12 % where the README said 95.06 %)."""
    planner, _ = _planner(3000)
    sensors, exciters = _admitted_layout(planner, 300)
    first, second = (certify_d(planner, sensors, exciters, "first-order", 800) for _ in range(2))
    assert first[:3] == second[:3] and first[3].spent == second[3].spent
