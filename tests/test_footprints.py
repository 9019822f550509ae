"""Mountable together: no hit on an accelerometer's footprint (half a base plus half a tip from its centre, on
its side of the wall), no two accelerometers closer than a base, on the plans of every bundled and CAD body."""

import numpy as np
import pytest
import session_cache
from conftest import bundled
from test_cli import massline
from test_diagnosability import default_plan as diagnosable_default
from test_mountable import CAD, cad_plan

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.placement.diagnosable_plan import minimal_budget
from massline.placement.footprints import (
    Footprint,
    Sites,
    check_fixed,
    conflicts,
    hits_blocked,
    sensors_blocked,
    spacing,
)
from massline.placement.on_surface import is_plate, plan
from massline.placement.planner import Budget
from massline.placement.selection import BlockProblem, greedy

FOOTPRINT = Footprint(10e-3, 6e-3)  # the defaults: a 10 mm base, a 6 mm tip → 8 mm from hit to accelerometer
UP, DOWN, SIDE = np.array([0.0, 0, 1]), np.array([0.0, 0, -1]), np.array([1.0, 0, 0])


def sites(*rows) -> Sites:
    """Sites from (x, y, z in mm, normal) rows."""
    return Sites(np.array([1e-3 * np.asarray(r[:3], float) for r in rows]), np.array([r[3] for r in rows]))


def test_hit_reach_is_half_the_base_plus_half_the_tip():
    assert FOOTPRINT.hit_reach == pytest.approx(8e-3, rel=1e-12)


def test_hits_within_the_reach_on_the_same_side_are_blocked():
    accelerometer = sites((0, 0, 0, UP))
    candidates = sites((7.9, 0, 0, UP), (8.1, 0, 0, UP), (0, 5, 0, UP), (0, 0, -3, DOWN), (0, 5, 0, SIDE))
    blocked = hits_blocked(candidates, accelerometer, FOOTPRINT)
    # 7.9 mm and 5 mm on the same face: blocked; 8.1 mm: clear; 3 mm behind a thin wall (n_s·n_h = −1): clear;
    # a face at right angles (n_s·n_h = 0 > −0.5) is not behind the wall: blocked
    assert blocked.tolist() == [True, False, True, False, True]


def test_accelerometers_keep_a_base_apart_whatever_their_face():
    placed = sites((0, 0, 0, UP))
    candidates = sites((9.9, 0, 0, UP), (10.1, 0, 0, UP), (0, 0, -3, DOWN), (30, 0, 0, UP))
    hits = sites((30, 4, 0, UP))
    blocked = sensors_blocked(candidates, placed, hits, FOOTPRINT)
    # 9.9 mm from the accelerometer; 3 mm behind it (two accelerometers on a thin wall still clash); 4 mm from a hit
    assert blocked.tolist() == [True, False, True, True]


def test_nothing_placed_blocks_nothing():
    candidates = sites((0, 0, 0, UP), (1, 0, 0, UP))
    assert not sensors_blocked(candidates, Sites.none(), Sites.none(), FOOTPRINT).any()
    assert not hits_blocked(candidates, Sites.none(), FOOTPRINT).any()


def test_spacing_of_a_point_from_the_others():
    need = spacing(1, UP, np.array([0, 0, 1]), np.array([UP, DOWN, UP]), FOOTPRINT)
    np.testing.assert_allclose(need, [8e-3, 0.0, 0.0], rtol=1e-12)  # a hit: 8 mm from an accelerometer facing it
    need = spacing(0, UP, np.array([0, 1]), np.array([DOWN, DOWN]), FOOTPRINT)
    np.testing.assert_allclose(need, [10e-3, 0.0], rtol=1e-12)


def test_conflicts_name_the_pairs_and_their_distance():
    sensors = sites((0, 0, 0, UP), (6, 0, 0, UP), (6, 0, 0, UP), (40, 0, 0, UP))  # lines 1, 2 one triaxial point
    hits = sites((40, 5, 0, UP), (0, 0, -2, DOWN))
    found = conflicts(sensors, hits, FOOTPRINT)
    kinds = [(k, i, j) for k, i, j, _ in found]
    assert kinds == [("sensors", 0, 1), ("sensors", 0, 2), ("hit", 3, 0)]
    np.testing.assert_allclose([d for *_, d in found], [6e-3, 6e-3, 5e-3], rtol=1e-12)


def test_fixed_lines_that_conflict_are_refused_naming_both():
    with pytest.raises(MasslineError, match=r"--fixed-exciter 1 is 5 mm from --fixed-sensor 2 on the same side"):
        check_fixed(sites((40, 0, 0, UP), (0, 0, 0, UP)), sites((3, 4, 0, UP)), FOOTPRINT)
    with pytest.raises(MasslineError, match=r"--fixed-sensor 1 and --fixed-sensor 2 are 6 mm apart"):
        check_fixed(sites((0, 0, 0, UP), (6, 0, 0, UP)), Sites.none(), FOOTPRINT)
    check_fixed(sites((0, 0, 0, UP)), sites((0, 0, -3, DOWN)), FOOTPRINT)  # a driving point from behind: fine


def test_greedy_keeps_the_chosen_a_spacing_apart_and_off_the_disallowed():
    rng = np.random.default_rng(3)
    blocks = rng.normal(size=(40, 1, 3))
    sites_m = np.column_stack([np.arange(40) * 4e-3, np.zeros(40), np.zeros(40)])  # a row 4 mm apart
    allowed = np.ones(40, bool)
    allowed[::7] = False
    problem = BlockProblem(blocks, np.zeros(40, int), (6,), np.zeros((3, 3)), allowed=allowed, sites=sites_m,
                           spacing=10e-3)  # fmt: skip
    chosen = greedy(problem)
    assert len(chosen) == 6 and allowed[chosen].all()
    gaps = np.abs(sites_m[chosen, 0][:, None] - sites_m[chosen, 0][None])
    assert gaps[~np.eye(6, dtype=bool)].min() >= 10e-3 - 1e-15


def assert_mountable_together(p, footprint: Footprint):
    """No hit closer than half a base plus half a tip to an accelerometer on its side, no two accelerometers at
    distinct points closer than a base; every point planned (none fixed) on its candidate's flat patch."""
    normals = p.candidates.normals
    S, E = Sites(p.sensors.points, normals[p.sensor_nodes]), Sites(p.exciters.points, normals[p.exciter_nodes])
    assert conflicts(S, E, footprint) == []
    gap = np.linalg.norm(S.points[:, None] - E.points[None], axis=2)
    same_side = S.normals @ E.normals.T >= -0.5
    assert gap[same_side].min(initial=np.inf) >= footprint.hit_reach
    apart = np.linalg.norm(S.points[:, None] - S.points[None], axis=2)
    assert apart[apart > 1e-12].min(initial=np.inf) >= footprint.sensor_base


BODIES = ("plate", "structure", "bracket")


@pytest.fixture(scope="module", params=BODIES)
def minimal_plan(request):
    body = bundled(request.param)
    search = lambda: plan(body, minimal_budget(is_plate(body)), certify_steps=5000)  # noqa: E731
    return session_cache.value("minimal plan", search, request.param)


@pytest.mark.slow
def test_minimal_plans_of_the_bundled_bodies_are_mountable_together(minimal_plan):
    assert_mountable_together(minimal_plan, FOOTPRINT)


@pytest.fixture(scope="module", params=BODIES)
def default_plan(request):
    """The default plan as test_diagnosability searches it (uncertified: the footprints do not depend on the
    certificate), computed once this session."""
    return diagnosable_default(request.param)[1]


@pytest.mark.slow
def test_default_plans_of_the_bundled_bodies_are_mountable_together(default_plan):
    assert default_plan.minimal is not None
    assert_mountable_together(default_plan, FOOTPRINT)
    assert_mountable_together(default_plan.minimal, FOOTPRINT)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(CAD))
def test_plans_of_the_cad_parts_are_mountable_together(name):
    options = CAD[name][2]
    assert_mountable_together(cad_plan(name)[1], Footprint(options.sensor_base, options.hammer_tip))


def test_fixed_lines_kept_apart_from_the_planned_ones():
    body = bundled("structure")
    fixed = Lines([[0.006, 0.06, 0.15]], [[0.0, 0.0, 1.0]])  # the column's top
    p = plan(body, Budget(6, 3), fixed_sensors=fixed, fixed_exciters=Lines([[0.16, 0.06, 0.006]], [[-1.0, 0, 0]]),
             certify_steps=2500)  # fmt: skip
    normals = np.vstack([[0.0, 0, 1], p.candidates.normals[p.sensor_nodes[1:]]])
    hit_normals = np.vstack([[-1.0, 0, 0], p.candidates.normals[p.exciter_nodes[1:]]])
    assert conflicts(Sites(p.sensors.points, normals), Sites(p.exciters.points, hit_normals), FOOTPRINT) == []


def test_conflicting_fixed_lines_are_refused_before_planning(tmp_path):
    run = massline(
        "plan", "structure", "--out", tmp_path / "plan", "--fixed-sensor", "0.006", "0.06", "0.15", "0", "0", "1",
        "--fixed-exciter", "0.009", "0.06", "0.15", "0", "0", "-1",
    )  # fmt: skip
    assert run.returncode == 2 and len(run.stderr.strip().splitlines()) == 1
    assert "--fixed-exciter 1 is 3 mm from --fixed-sensor 1" in run.stderr

