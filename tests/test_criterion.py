"""Criteria D, A and E: certified bounds against brute force; E raises λ_min on every bundled body."""

import itertools
import json
from dataclasses import replace

import numpy as np
import pytest
import trimesh
from conftest import bundled
from test_cli import massline

from massline.core import Lines
from massline.placement.certificate import certify
from massline.placement.certification import CertificateError, certify_d
from massline.placement.criteria import CRITERIA, D
from massline.placement.criterion_relaxation import relax_criterion
from massline.core.information import NoiseModel
from massline.core.model import RigidModel
from massline.placement.on_surface import plan
from massline.placement.planner import Budget, CandidateLines, Planner, plan_on_candidates
from massline.placement.selection import best_gains, gains, greedy, swap

MINIMAL = {"structure": Budget(6, 3), "bracket": Budget(6, 3), "plate": Budget(3, 3)}


def _small_planner(seed: int, criterion=D) -> Planner:
    """12 sensor and 9 exciter candidates on the structure, budget 6 × 3."""
    body = bundled("structure")
    points, faces = trimesh.sample.sample_surface(body.mesh, 21, seed=seed)
    lines = Lines(points, body.mesh.face_normals[faces])
    s_side, e_side = CandidateLines.single(lines[np.arange(12)]), CandidateLines.single(lines[np.arange(12, 21)])
    return Planner(RigidModel(body.nominal), s_side, e_side, Budget(6, 3), NoiseModel(), criterion=criterion)


def _side_problems(seed: int, criterion):
    """A sensor problem (12 candidates, 6 to choose) and an exciter problem (9, 3) on the structure."""
    rng = np.random.default_rng(seed)
    planner = _small_planner(seed, criterion)
    exciters, sensors = list(rng.choice(9, 3, replace=False)), list(rng.choice(12, 6, replace=False))
    return planner.sensor_problem(planner.exciter_rows(exciters)), planner.exciter_problem(planner.sensor_rows(sensors))


def _brute_force(problem) -> float:
    k = problem.budgets[0]
    return max(problem.value(list(c)) for c in itertools.combinations(range(len(problem.blocks)), k))


@pytest.mark.parametrize("name", ["D", "A", "E"])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_certified_bound_is_above_the_brute_force_optimum(name, seed):
    for problem in _side_problems(seed, CRITERIA[name]):
        chosen = swap(problem, greedy(problem))
        best = _brute_force(problem)
        if name == "D":
            bound = certify(problem, chosen, steps=5000)[0]
        else:
            bound = relax_criterion(problem, CRITERIA[name], chosen)
        assert problem.value(chosen) <= best + 1e-9 * abs(best)
        assert bound >= best - 1e-7 * abs(best), (bound, best)
        assert CRITERIA[name].efficiency(problem.value(chosen), bound, problem.p) <= 1 + 1e-9


@pytest.mark.parametrize("seed", [0, 1])
def test_certified_sides_bound_every_change_of_one_side(seed):
    """certify_d's U_s bounds every sensor set at the final exciters, U_e every exciter set at the final
    sensors (brute force), and the layout it returns is no worse than the one it was given."""
    planner = _small_planner(seed)
    sensors, exciters = list(range(6)), [0, 1, 2]
    start = planner.exciter_problem(planner.sensor_rows(sensors)).value(exciters)
    sensors, exciters, bounds, _ = certify_d(planner, sensors, exciters, "first-order", 5000)
    sp, ep = (
        planner.sensor_problem(planner.exciter_rows(exciters)),
        planner.exciter_problem(planner.sensor_rows(sensors)),
    )
    assert ep.value(exciters) >= start - 1e-9
    assert bounds["sensors"] >= _brute_force(sp) - 1e-7 * abs(bounds["sensors"])
    assert bounds["exciters"] >= _brute_force(ep) - 1e-7 * abs(bounds["exciters"])


@pytest.fixture(scope="module", params=[0, 1])
def small_plan(request):
    """The planner's 6 × 3 layout among 12 sensor and 9 exciter candidates on the structure, certified."""
    planner = _small_planner(request.param)
    return planner, plan_on_candidates(planner.model, planner.s, planner.e, Budget(6, 3), certify_steps=5000)


def test_the_stated_d_efficiency_is_the_certificates_and_at_most_the_true_one(small_plan):
    """The plan states its certificate's own efficiency, exp((log det F − max(U_s, U_e))/p), and that is at most
    its true efficiency against the best admissible layout changing one side (brute force over all 924 sensor and
    84 exciter sets): a bound made optimistic states more than the truth, or more than 100 %."""
    planner, plan = small_plan
    p = plan.model.p
    own = np.exp((plan.candidate_log_det - max(plan.d_bounds.values())) / p)
    assert plan.d_efficiency_lower_bound == pytest.approx(own, rel=1e-12)
    assert plan.efficiency_lower_bound == pytest.approx(own, rel=1e-12)
    sensors, exciters = list(plan.sensor_nodes), list(plan.exciter_nodes)
    sp = planner.sensor_problem(planner.exciter_rows(exciters))
    ep = planner.exciter_problem(planner.sensor_rows(sensors))
    best = max(
        max(sp.value(list(c)) for c in itertools.combinations(range(12), 6) if planner.admits(list(c), exciters)),
        max(ep.value(list(c)) for c in itertools.combinations(range(9), 3) if planner.admits(sensors, list(c))),
    )
    assert plan.d_efficiency_lower_bound <= np.exp((sp.value(sensors) - best) / p) + 1e-9


def test_a_bound_below_its_layout_is_raised_not_clipped(small_plan):
    """A bound under the layout's own log det is no bound: stating min(…, 100 %) would hide it."""
    plan = small_plan[1]
    below = replace(plan, d_bounds={side: plan.candidate_log_det - 0.1 for side in plan.d_bounds})
    with pytest.raises(CertificateError, match="below the layout's own log det F"):
        below.d_efficiency_lower_bound
    level = replace(plan, d_bounds={side: plan.candidate_log_det - 1e-12 for side in plan.d_bounds})
    assert level.d_efficiency_lower_bound == 1.0  # equal to the layout but for rounding: the layout is the best


def test_lazy_best_gains_are_the_exhaustive_ones_even_near_singular():
    """The lazy order's bound (Hadamard and the eigen split) never skips a block that belongs in the top."""
    problem = _side_problems(4, D)[0]
    for chosen in ([0, 1, 2, 3, 4, 5], [0, 1, 2, 3, 4]):  # the second leaves M nearly singular
        M = problem.information(chosen) + problem.regulariser()
        allowed = np.ones(len(problem.blocks), bool)
        allowed[chosen] = False
        index, value = best_gains(problem.blocks, np.linalg.inv(M), allowed, count=3, chunk=2)
        exhaustive = np.where(allowed, gains(problem.blocks, np.linalg.inv(M)), -np.inf)
        np.testing.assert_allclose(value, np.sort(exhaustive)[::-1][:3], rtol=1e-9)


def test_criterion_scores_are_the_criterion_of_the_updated_information():
    problem = _side_problems(3, D)[0]
    M = problem.information([0, 1, 2, 3]) + problem.regulariser()
    for criterion in CRITERIA.values():
        expected = [criterion.value(M + b.T @ b) for b in problem.blocks]
        np.testing.assert_allclose(criterion.scores(problem.blocks, M), expected, rtol=1e-8)


@pytest.fixture(scope="module")
def d_and_e_plans():
    return {name: {c: plan(bundled(name), budget, criterion=c) for c in "DE"} for name, budget in MINIMAL.items()}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(MINIMAL))
def test_criterion_e_raises_the_smallest_eigenvalue(d_and_e_plans, name):
    d, e = d_and_e_plans[name]["D"], d_and_e_plans[name]["E"]
    assert e.smallest_eigenvalue > d.smallest_eigenvalue, (e.smallest_eigenvalue, d.smallest_eigenvalue)
    candidate = e.sliding.before  # the bounds cover the candidate layouts; sliding may go beyond them
    assert candidate <= e.bounds["sensors"] + 1e-9 and candidate <= e.bounds["exciters"] + 1e-9
    assert e.value >= candidate
    assert 0 < e.efficiency_lower_bound <= 1
    assert d.criterion is D and d.value == pytest.approx(d.log_det)


def test_plan_criterion_e_on_the_command_line(tmp_path):
    run = massline("plan", "plate", "--sensors", "3", "--criterion", "E", "--out", tmp_path / "p")
    assert run.returncode == 0, run.stderr
    c = json.loads((tmp_path / "p" / "plan.json").read_text())["criterion"]
    assert c["name"] == "E" and c["value"] == pytest.approx(c["smallest_eigenvalue"])
    assert 0 < c["efficiency_lower_bound"] <= 1
    assert "eq. (10)" in c["condition_systems"]["kinematic"]
    assert "E-efficiency" in run.stdout and "eq. (1" in run.stdout
    assert "E-efficiency" in (tmp_path / "p" / "report.html").read_text()
