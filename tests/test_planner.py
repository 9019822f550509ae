"""The planner: better than random, EfI and hand layouts; certified; honest 1-σ."""

import itertools

import numpy as np
import pytest
import trimesh
from conftest import bundled
from likelihood import maximum_likelihood

from massline.core import Lines, Masslines, synthesise
from massline.core.accuracy import layout_worst_std
from massline.placement.candidates import CandidateOptions, candidate_lines
from massline.core.errors import MasslineError
from massline.placement.hand_layouts import (
    bracket_exciters,
    bracket_sensors,
    plate_table1,
    structure_exciters,
    structure_sensors,
)
from massline.core.information import NoiseModel, fisher, log_det, weighted_sensitivities
from massline.core.model import RigidModel
from massline.placement.on_surface import plan
from massline.placement.planner import Budget, CandidateLines, Planner, plan_on_candidates
from massline.core.properties import property_vector
from massline.placement.selection import effective_independence

MINIMAL = {"structure": Budget(6, 3), "bracket": Budget(6, 3), "plate": Budget(3, 3)}
# How much better than the median random layout the plan must be. The plate's 3 × 3 out-of-plane
# problem is forgiving: random spread points do well, and even a layout optimised for the worst
# 1-σ itself is only ~4.3× better than their median, so 5× is out of reach there (see the note).
RANDOM_FACTOR = {"structure": 5.0, "bracket": 5.0, "plate": 4.0}
HAND = {
    "structure": (structure_sensors(), structure_exciters()),
    "bracket": (bracket_sensors(), bracket_exciters()[:3]),
    "plate": plate_table1(),
}


@pytest.fixture(scope="module")
def minimal_plans():
    return {name: plan(bundled(name), budget) for name, budget in MINIMAL.items()}


def _worst(model, sensors, exciters, noise=NoiseModel()):
    return layout_worst_std(model, fisher(model, model.coordinates(sensors), model.coordinates(exciters), noise))


@pytest.mark.parametrize("name", list(MINIMAL))
def test_plan_beats_random_layouts_fivefold(minimal_plans, name):
    p = minimal_plans[name]
    sensors, exciters = candidate_lines(p.candidates, False, p.model.planar, False)
    rng = np.random.default_rng(7)
    budget = MINIMAL[name]
    worst = [
        _worst(
            p.model,
            sensors.lines[rng.choice(len(sensors.lines), budget.sensors, replace=False)],
            exciters.lines[rng.choice(len(exciters.lines), budget.exciters, replace=False)],
        )
        for _ in range(200)
    ]
    assert p.worst_relative_std * RANDOM_FACTOR[name] <= np.median(worst), (p.worst_relative_std, np.median(worst))


@pytest.mark.parametrize("name", list(MINIMAL))
def test_plan_beats_effective_independence(minimal_plans, name):
    """Backward leverage elimination (Kammer), alternated between the two sides like the planner."""
    p = minimal_plans[name]
    s_side, e_side = candidate_lines(p.candidates, False, p.model.planar, False)
    planner = Planner(p.model, s_side, e_side, MINIMAL[name], p.noise)
    reference = np.random.default_rng(0).choice(len(s_side), min(200, len(s_side)), replace=False)
    exciters = effective_independence(planner.exciter_problem(planner.sensor_rows(reference)))
    for _ in range(2):
        sensors = effective_independence(planner.sensor_problem(planner.exciter_rows(exciters)))
        exciters = effective_independence(planner.exciter_problem(planner.sensor_rows(sensors)))
    efi = _worst(p.model, *planner.layout(sensors, exciters))
    assert p.worst_relative_std < efi, (p.worst_relative_std, efi)


@pytest.mark.parametrize("name", list(MINIMAL))
def test_plan_beats_a_hand_layout_like_the_papers(name):
    sensors, exciters = HAND[name]
    budget = Budget(len(sensors), len(exciters))
    p = plan(bundled(name), budget)
    assert p.worst_relative_std < _worst(p.model, sensors, exciters)


@pytest.mark.parametrize("name", list(MINIMAL))
def test_minimal_layout_is_certified_within_95_percent(minimal_plans, name):
    p = minimal_plans[name]
    assert p.d_efficiency_lower_bound >= 0.95
    assert p.candidate_log_det <= min(p.bounds.values()) + 1e-9
    assert len(p.sensors) == MINIMAL[name].sensors and len(p.exciters) == 3


@pytest.mark.parametrize(
    "name,budget",
    [
        ("structure", Budget(12, 4)),
        ("bracket", Budget(12, 4)),
        ("plate", Budget(12, 4)),
        ("structure", Budget(0, 3, 4)),
    ],
)
def test_budgets_of_twelve_sensor_lines_are_certified_within_95_percent(name, budget):
    """The certificate bounds every layout of the candidates, footprints or not: the hits kept off the
    accelerometers' footprints (placement/footprints.py) cost the layout up to ~2 % of it."""
    p = plan(bundled(name), budget)
    assert p.d_efficiency_lower_bound >= 0.95
    assert len(p.sensors) == budget.sensors + 3 * budget.triaxial


def test_triaxials_are_three_lines_through_one_point():
    p = plan(bundled("structure"), Budget(3, 3, 2))
    groups = p.sensors.triaxial[p.sensors.triaxial >= 0]
    assert len(groups) == 6
    for g in np.unique(groups):
        lines = p.sensors[np.flatnonzero(p.sensors.triaxial == g)]
        assert np.allclose(lines.points, lines.points[0])
        assert np.allclose(np.abs(lines.directions @ lines.directions.T), np.eye(3))


def _surface_lines(mesh, n, seed):
    points, faces = trimesh.sample.sample_surface(mesh, n, seed=seed)
    return Lines(points, mesh.face_normals[faces])


def _exhaustive_best(planner, model, noise, n_s, n_e, k_s, k_e):
    """The best regular layout over every sensor 6-set × exciter 3-set."""
    g = weighted_sensitivities(model, planner.s_coords, planner.e_coords, noise)
    outer = np.einsum("ijk,ijl->ijkl", g, g)
    sensor_sets = np.array(list(itertools.combinations(range(n_s), k_s)))
    values = []
    for E in itertools.combinations(range(n_e), k_e):
        per_sensor = outer[:, list(E)].sum(axis=1)
        F = per_sensor[sensor_sets].sum(axis=1)
        sign, logdet = np.linalg.slogdet(F)
        values += [(v if s > 0 else -np.inf, tuple(S), E) for v, s, S in zip(logdet, sign, sensor_sets)]
    values.sort(key=lambda t: -t[0])
    for value, S, E in values:
        if planner.regular(*planner.layout(list(S), list(E))):
            return value
    return -np.inf


@pytest.mark.long  # 10 × 960,960 layouts' log det (a minute): the long tier
def test_exhaustive_search_finds_nothing_better_on_small_sets(structure):
    """Ten random instances of 16 sensor and 10 exciter candidate lines (26 ≤ 30)."""
    mesh = bundled("structure").mesh
    model, noise = RigidModel(structure), NoiseModel()
    wins = 0
    for seed in range(10):
        s_side = CandidateLines.single(_surface_lines(mesh, 16, seed))
        e_side = CandidateLines.single(_surface_lines(mesh, 10, 100 + seed))
        p = plan_on_candidates(model, s_side, e_side, Budget(6, 3), noise, seed=seed)
        planner = Planner(model, s_side, e_side, Budget(6, 3), noise)
        best = _exhaustive_best(planner, model, noise, 16, 10, 6, 3)
        wins += p.log_det >= best - 1e-9 * abs(best)
    assert wins >= 9


@pytest.mark.slow
@pytest.mark.parametrize(
    "name,budget", [("structure", Budget(6, 3)), ("plate", Budget(3, 3)), ("bracket", Budget(12, 4))]
)
def test_monte_carlo_reproduces_the_predicted_std(name, budget):
    """500 noisy draws through the weighted identifier: empirical 1-σ as Cramér–Rao predicts, within 4× the
    sampling error of a standard deviation from n draws (1/√(2(n − 1)) = 3.2 %, so 12.7 %). The noise is drawn
    here, from the noise model's definition (relative × |H| ⊕ floor / m, DESIGN.md) and its own generator, not
    through the NoiseModel whose information the prediction uses."""
    p = plan(bundled(name), budget)
    truth = synthesise(p.model.nominal, p.sensors, p.exciters)
    relative, floor = p.noise.relative, p.noise.floor / p.model.nominal.mass
    rng, n = np.random.Generator(np.random.PCG64DXSM(7)), 500
    draws = []
    for _ in range(n):
        noise = np.abs(truth.values) * relative * rng.standard_normal(truth.values.shape)
        noise += floor * rng.standard_normal(truth.values.shape)
        noisy = Masslines(truth.values + noise, p.sensors, p.exciters)
        draws.append(property_vector(maximum_likelihood(noisy, p.noise, p.model.planar)[0], p.model.planar))
    empirical = np.std(draws, axis=0, ddof=1)
    s = p.predicted_std
    predicted = np.concatenate([[s["mass"]], s["cog"], s["principal_moments"]])
    found = np.concatenate([empirical[:4], empirical[13:16]])
    observable = ~np.isnan(predicted)
    np.testing.assert_allclose(found[observable], predicted[observable], rtol=4 / np.sqrt(2 * (n - 1)))


def test_plan_respects_exclusions_and_fixed_sensors():
    body = bundled("structure")
    box = ((0.0, 0.0, 0.0), (0.16, 0.12, 0.0121))  # the whole base plate
    fixed = Lines([[0.006, 0.06, 0.15]], [[0.0, 0.0, 1.0]])
    p = plan(body, Budget(6, 3), CandidateOptions(exclude_boxes=(box,), edge_keepout=0.004), fixed_sensors=fixed)
    for lines in (p.sensors, p.exciters):
        inside = np.all((lines.points >= box[0]) & (lines.points <= box[1]), axis=1)
        assert not inside.any()
    assert p.d_efficiency_lower_bound > 0.9


@pytest.mark.parametrize(
    "budget,words",
    [
        (Budget(5, 3), "at least 6"),
        (Budget(6, 2), "minimum is 3"),
        (Budget(0, 3, 2), "two triaxial"),
        (Budget(2, 3), "at least 6"),
    ],
)
def test_budgets_below_the_minimum_say_what_is_missing(budget, words):
    with pytest.raises(MasslineError, match=words):
        plan(bundled("structure"), budget)


def test_too_few_usable_points():
    all_but_a_corner = (((0.003, -1, -1), (1, 1, 1)), ((-1, 0.003, -1), (1, 1, 1)), ((-1, -1, 0.003), (1, 1, 1)))
    with pytest.raises(MasslineError, match=r"only \d+ sensor candidates for a budget of 6"):
        plan(bundled("structure"), Budget(6, 3), CandidateOptions(exclude_boxes=all_but_a_corner))


def test_keepouts_leaving_only_degenerate_layouts():
    only_the_bottom_face = ((-1.0, -1.0, 1e-6), (1.0, 1.0, 1.0))
    with pytest.raises(MasslineError, match="degenerate"):
        plan(bundled("structure"), Budget(6, 3), CandidateOptions(exclude_boxes=(only_the_bottom_face,)))


def test_plan_is_regular_and_reports_conditions(minimal_plans):
    for p in minimal_plans.values():
        assert set(p.condition) == {"kinematic", "translation", "rotation"}
        assert all(1 <= v < 1e4 for v in p.condition.values())
        assert np.isfinite(
            log_det(fisher(p.model, p.model.coordinates(p.sensors), p.model.coordinates(p.exciters), p.noise))
        )
