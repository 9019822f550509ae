"""Diagnosable plans: one faulty channel or hit can be located (placement/diagnosability.py).

The leverage algebra on hand layouts; the default plans (the cheapest diagnosable) of the bundled bodies
are diagnosable and the paper's minimal ones are not; and blind: one faulty channel (polarity, gain,
direction) concealed in virtual tests of the default and the minimal plan (virtual/scenarios.py), diagnosed
from the UFF, scored as the blind suite scores it (tests/blind_measures.py): located at its channel on the
default plan, not on the minimal one (no redundancy). ``python tests/test_diagnosability.py SEEDS [BODY ...]``
prints the full table (default: the three bodies).
"""

from __future__ import annotations

import sys
import tempfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest
import session_cache
from blind_measures import placed
from test_diagnose_blind import BENCHES

from massline.identify.diagnose.effects import BY_NAME
from massline.identify.diagnose.screens import roomy
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.meshes import BUNDLED
from massline.placement.diagnosability import diagnosability
from massline.placement import diagnosable_plan
from massline.placement.diagnosability import UndiagnosableError
from massline.placement.diagnosable_plan import budgets, cheapest_diagnosable
from massline.core.lines import Lines
from massline.meshes.loader import load_body
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.virtual.elastic import Material
from massline.virtual.scenarios import Bench, Conditions, scenario, write_case

CHANNEL_FAULTS = ("sensor_polarity", "sensor_gain", "sensor_direction")
PLATE_FAULTS = ("sensor_polarity", "sensor_gain")
CONDITIONS = Conditions("soft", "direct")
BODY = RigidBody(10.0, np.array([0.01, 0.02, 0.0]), np.diag([0.2, 0.3, 0.4]))


def corner_lines(count: int) -> Lines:
    """``count`` lines at the corners and edges of a 0.4 m cube, cycling through x, y, z."""
    rng = np.random.default_rng(3)
    points = rng.choice([-0.2, 0.2], size=(count, 3)) + rng.uniform(-0.05, 0.05, (count, 3))
    return Lines(points, np.eye(3)[np.arange(count) % 3])


def hits(count: int) -> Lines:
    return Lines(np.random.default_rng(5).uniform(-0.2, 0.2, (count, 3)), np.eye(3)[(np.arange(count) + 1) % 3])


def test_seven_channels_see_a_fault_but_cannot_locate_it():
    d = diagnosability(RigidModel(BODY), corner_lines(7), hits(4))
    assert np.all(d.channel_leverage < 1) and np.allclose(d.channel_confusion, 1.0)
    assert not d.diagnosable and "no redundancy" in d.failures[0]
    assert d.hidden(0) == ("sensor_gain", "sensor_polarity", "sensor_direction")


def test_the_minimal_layout_checks_nothing():
    d = diagnosability(RigidModel(BODY), corner_lines(6), hits(3))
    assert np.allclose(d.channel_leverage, 1.0) and np.allclose(d.hit_leverage, 1.0)
    assert d.weak_channels == list(range(6)) and d.weak_hits == [0, 1, 2]


def test_a_motion_only_two_channels_see_leaves_their_faults_confused():
    """Every line but the first two is along z or meets the z axis: only those two see a turn about z."""
    z = [[0.2, 0.2, 0.1], [-0.2, 0.2, 0.1], [0.2, -0.2, -0.1], [-0.2, -0.1, 0.0]]
    on_axis = [[0.0, 0.0, 0.2], [0.0, 0.0, -0.2], [0.0, 0.0, 0.1], [0.0, 0.0, -0.1]]
    points = [[0.1, 0.2, 0.0], [-0.1, -0.2, 0.1], *z, *on_axis]
    directions = [[1, 0, 0], [1, 0, 0]] + [[0, 0, 1]] * 4 + [[1, 0, 0], [0, 1, 0], [0, 1, 0], [1, 0, 0]]
    d = diagnosability(RigidModel(BODY), Lines(points, directions), hits(5))
    assert d.channel_confusion[0] > 0.999 and d.channel_confusion[1] > 0.999
    assert d.channel_confusion[2:6].max() < 0.999 and d.weak_channels[:2] == [0, 1]  # (7, 8: alone on a_y)


def test_leverages_sum_to_the_motions_and_no_hit_is_indispensable():
    model = RigidModel(BODY)
    d = diagnosability(model, corner_lines(14), hits(6))
    assert d.channel_leverage.sum() == pytest.approx(6.0)
    assert 0 < d.hit_leverage.min() and d.hit_leverage.max() < 1  # six hits: any five identify the body


def test_budgets_start_at_the_cheapest_that_can_be_diagnosable():
    assert [(b.sensors, b.exciters) for b in list(budgets(False))[:4]] == [(8, 4), (8, 5), (9, 4), (8, 6)]
    assert next(budgets(True)).sensors == 5


@dataclass(frozen=True)
class Planned:
    """What the default plan's search reads of a plan: its size and worst relative 1-σ."""

    sensors: tuple
    exciters: tuple
    worst_relative_std: float
    minimal: object = None
    search: object = None


def planner_of(worst: dict):
    """A stand-in for ``on_surface.plan``: the plan of each budget with the worst 1-σ ``worst`` gives it (the
    minimal budget's for the undiagnosable plan), no diagnosable layout where it gives none."""

    def planned(body, budget, *args, diagnosable=False, **kwargs):
        size = (budget.sensors, budget.exciters)
        if diagnosable and size not in worst:
            raise UndiagnosableError(f"none of {size}")
        return Planned((0,) * size[0], (0,) * size[1], worst[size if diagnosable else "minimal"])

    return planned


def test_a_diagnosable_layout_less_accurate_than_the_minimal_one_is_passed_over(monkeypatch):
    """The default is the cheapest diagnosable budget no less accurate (worst 1-σ) than the paper's minimal layout:
    8 × 4 at 1.5 % against the minimal 1.0 % is passed over (said in the search's sentence), 8 × 5 has none, 9 × 4
    at 0.9 % is the plan; where no budget is as accurate, the first diagnosable one is, and the sentence says so."""
    body = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density)
    monkeypatch.setattr(diagnosable_plan, "plan", planner_of({"minimal": 0.010, (8, 4): 0.015, (9, 4): 0.009}))
    p = cheapest_diagnosable(body)
    assert (len(p.sensors), len(p.exciters), p.worst_relative_std) == (9, 4, 0.009)
    assert p.minimal.worst_relative_std == 0.010 and not p.search.stopped
    assert "1 with one less accurate than the minimal plan (8 lines × 4 hits at 1.50%)" in p.search.what
    monkeypatch.setattr(diagnosable_plan, "plan", planner_of({"minimal": 0.010, (8, 4): 0.015, (9, 4): 0.012}))
    p = cheapest_diagnosable(body)
    assert (len(p.sensors), len(p.exciters), p.worst_relative_std) == (8, 4, 0.015)
    assert "less accurate than the minimal plan: none as accurate up to the last budget" in p.search.what


@lru_cache(maxsize=None)
def default_plan(name: str):
    """The bundled body ``name`` and its diagnosable default plan (uncertified), searched once this session."""
    mesh = load_body(BUNDLED[name].path, "m", BUNDLED[name].density)
    return mesh, session_cache.value("diagnosable default plan", lambda: cheapest_diagnosable(mesh, certify_steps=0), name)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["plate", "structure", "bracket"])
def test_default_plans_are_diagnosable_and_minimal_ones_are_not(name):
    _, p = default_plan(name)
    assert p.diagnosability.diagnosable, p.diagnosability.failures
    assert not p.minimal.diagnosability.diagnosable
    assert len(p.exciters) >= 4 and len(p.sensors) >= (5 if p.model.planar else 8)
    assert p.log_det >= p.minimal.log_det  # more lines and hits: more information (D), though its worst
    # 1-σ may be larger: the bracket's diagnosable 10 × 4 of an earlier search had 1.50 % against the minimal
    # 6 × 3's 1.31 % (the report states the cost; --criterion E plans for the worst 1-σ)


def bench(name: str, plan) -> Bench:
    """The blind suite's bench of ``name`` on ``plan``'s layout."""
    mesh = load_body(BUNDLED[name].path, "m", BUNDLED[name].density)
    youngs, poisson = BENCHES[name][1]
    modes = session_cache.fe_modes(mesh.mesh, Material(youngs, poisson, mesh.density), 12)
    fmax = modes.frequencies_hz[0] / 2.5
    return Bench(mesh.nominal, plan.sensors, plan.exciters, modes, fmax, 2000, mesh.mesh, name == "plate")


def located(b: Bench, fault: str, seed: int, folder: Path) -> tuple[bool, bool, bool]:
    """Whether diagnose's first fault sits at the faulty channel, or, with no fault named, its ``unexplained``
    finding does (located), whether the first fault is also ``fault`` (named), and whether the layout had
    redundancy."""
    recording, truth = scenario(b, fault, seed, CONDITIONS, effects=BY_NAME)
    path = folder / f"{fault}-{seed}.uff"
    write_case(path, recording, CONDITIONS)
    band = truth["planned_band_hz"]
    found = diagnose_recording(to_recording(read_uff(path)), band and tuple(band), b.body)
    faults = [x for x in found.findings if x.kind == "fault"]
    first = faults or [x for x in found.findings if x.kind == "unexplained" and x.channels]
    at = bool(first) and first[0].effect.startswith(("sensor", "unexplained")) and placed(truth["faults"][0], first[0])
    return at, at and first[0].effect == fault, roomy(found.layout)


def table(name: str, seeds, folder: Path) -> dict:
    """(plan, fault) → (located, named, cases, with redundancy) on the default and the minimal plan of ``name``."""
    _, p = default_plan(name)
    out = {}
    for label, layout in (("default", p), ("minimal", p.minimal)):
        b = bench(name, layout)
        for fault in PLATE_FAULTS if name == "plate" else CHANNEL_FAULTS:
            runs = [located(b, fault, s, folder) for s in seeds]
            out[label, fault] = tuple(sum(r[k] for r in runs) for k in (0, 1)) + (len(runs), sum(r[2] for r in runs))
    return out


@pytest.mark.long  # eight virtual tests of the structure diagnosed (minutes): the long tier
def test_a_faulty_channel_is_located_on_the_default_plan_and_not_on_the_minimal(tmp_path):
    """Located: the first fault named sits at the faulty channel, or, none named, the unexplained finding does.
    Named too in 5 of these 6: a −29 % gain on one channel is fitted as well by an 11 mm shift and a tilt of its
    sensor (ΔBIC 57 between them with the tails modelled, the gain itself fitted −22 %): the channel is found,
    what is wrong with it is not."""
    _, p = default_plan("structure")
    default, minimal = bench("structure", p), bench("structure", p.minimal)
    runs = [located(default, fault, seed, tmp_path) for fault in CHANNEL_FAULTS for seed in (0, 1)]
    assert np.mean([at for at, _, _ in runs]) >= 0.95, runs
    assert np.mean([named for _, named, _ in runs]) >= 5 / 6, runs
    for fault in ("sensor_polarity", "sensor_gain"):  # the minimal plan's direction faults: see docs/validation.md
        _, named, redundant = located(minimal, fault, 0, tmp_path)  # a fault may sit at the channel (3 of 10)
        assert not named and not redundant


def markdown(name: str, results: dict, sizes: dict) -> list[str]:
    """docs/validation.md's rows of ``name``: per plan, each fault's "located, named of cases" (— where not run)."""
    rows = []
    for label, q in sizes.items():
        cells = [
            "{}, {} of {}".format(*results[label, f][:3]) if (label, f) in results else "—" for f in CHANNEL_FAULTS
        ]
        rows.append(f"| {name} | {label} {len(q.sensors)} × {len(q.exciters)} | " + " | ".join(cells) + " |")
    return rows


if __name__ == "__main__":
    seeds = range(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
    lines = ["| body | plan | polarity: located, named | gain | direction |", "|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as folder:
        print(f"{'body':>10} {'plan':>8} {'lines×hits':>10} {'worst σ':>8} {'fault':>17} located, named / cases")
        for name in sys.argv[2:] or ("structure", "plate", "bracket"):
            _, p = default_plan(name)
            sizes = {"default": p, "minimal": p.minimal}
            results = table(name, seeds, Path(folder))
            for (label, fault), (at, named, n, _) in results.items():
                q = sizes[label]
                shape = f"{len(q.sensors)}×{len(q.exciters)}"
                print(
                    f"{name:>10} {label:>8} {shape:>10} {q.worst_relative_std:8.2%} {fault:>17} {at}, {named} / {n}",
                    flush=True,
                )
            lines += markdown(name, results, sizes)
    print("\n" + "\n".join(lines))


def test_a_planners_known_layouts_keep_their_excess_and_count_as_work():
    """The planner keeps each layout's excess (a search meets a third of its trials again): asked again, alone or
    in a stack with others, a layout gets the value a fresh planner computes for it, and every trial asked counts
    one unit of the search's work, known or not."""
    from massline.core.information import NoiseModel
    from massline.placement.alternation import Planner
    from massline.placement.candidates import CandidateLines
    from massline.placement.diagnosability import excesses
    from massline.placement.planner import Budget
    from massline.placement.work import Work
    import trimesh

    body = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density)
    rng = np.random.default_rng(4)
    points, faces = trimesh.sample.sample_surface(body.mesh, 60, seed=4)
    side = CandidateLines.single(Lines(points, body.mesh.face_normals[faces]))
    model, noise = RigidModel(body.nominal), NoiseModel()
    made = lambda: Planner(model, side, side, Budget(8, 4), noise, diagnosable=True, work=Work(10**6, "trials"))  # noqa: E731
    trials = [(sorted(rng.choice(60, 8, replace=False)), sorted(rng.choice(60, 4, replace=False))) for _ in range(30)]
    planner = made()
    first = planner.violations(trials[:20])
    again = planner.violations(trials[10:] + trials[:3] + trials[:3])
    alone = [planner.violation(*t) for t in trials[25:]]
    assert planner.work.spent == 20 + 26 + 5
    S, W = (np.stack([model.coordinates(side.lines[np.asarray(t[i])]) for t in trials]) for i in (0, 1))
    fresh = excesses(model, S, W, noise)
    np.testing.assert_array_equal(first, fresh[:20])
    np.testing.assert_array_equal(again, np.concatenate([fresh[10:], fresh[:3], fresh[:3]]))
    np.testing.assert_array_equal(alone, fresh[25:])
    assert (fresh > 0).any()  # trials short of diagnosable: values that differ from layout to layout
