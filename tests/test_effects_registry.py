"""Every effect of the registry (massline.identify.diagnose.effects), end to end, on small synthetic cases.

For each effect: it is well formed (name, kind, unit, its own module); it is simulated — a virtual test with it
differs from the same test without it: an ``--effect`` on the lines, the support (suspension) on a stiff cord
instead of none, the elastic modes (residual flexibility) with a mode instead of none; it is documented in
``massline simulate --help`` when it is an ``--effect``; it is diagnosable — its model in the diagnosis has
parameters the data determine (a block's fit recovers exact masslines, a discrete fix is the screen's first
proposal, a tail law is fitted, a mass loading is weighed, lines set aside are found), unless it is knowingly not diagnosed (``model``
None: transverse sensitivity, estimated under the datasheet's prior in every fit); and the finding it makes is
described (its sentence renders) and round-trips through the diagnose JSON with its name and kind.
"""

from __future__ import annotations

import json
import numpy as np
import pytest

from massline.cli.app import run as run_cli
from massline.core.effect_names import KINDS, PERTURBS
from massline.core.files import to_json
from massline.core.lines import Lines
from massline.core.model import RigidModel
from massline.identify.diagnose.effect_fit import base_fit, plausible, refit
from massline.identify.diagnose.effect_fit import fit
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import BY_NAME, EFFECTS, effect_help, parse_effect, simulated
from massline.identify.diagnose.effects.base import Block, Scene
from massline.identify.diagnose.finding import Finding, accepted_finding, finding_payload, mains_finding
from massline.identify.diagnose.gauge_mass import gauge_mass
from massline.identify.diagnose.mass_loading import mass_loading
from massline.identify.diagnose.notes import finding_note
from massline.identify.diagnose.row_factors import row_findings
from massline.identify.diagnose.screens import discrete_fixes, kinematic_matrix
from massline.identify.mains import find_mains
from massline.identify.pipeline import identify_recording
from massline.identify.sensor_mass import point_mass_theta
from massline.identify.tails import TAIL_LAWS, BandData
from massline.meshes import BUNDLED
from massline.meshes.loader import load_body
from massline.placement.hand_layouts import structure_exciters
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise
from massline.virtual.scenarios import FAULTS
from massline.virtual.suspension import Cord, Suspension

SAMPLE = {"degrees": 10.0, "fraction": 0.2, "m": 0.01, "kg": 0.05, "s": 1e-4, "Hz": 300.0}  # a clear size in each unit
EXACT = Acquisition(100.0, 40, Noise(1e-8, 0.0), dc_line=False)  # 40 lines to 100 Hz, all but exact
MAINS_HZ = 50.0  # a frequency effect's sample place


@pytest.fixture(scope="module")
def body():
    return load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density).nominal


@pytest.fixture(scope="module")
def sensors():
    """Ten uniaxial accelerometers (one channel per accelerometer: a block's target is its line)."""
    rng = np.random.default_rng(2)
    return Lines(rng.normal(size=(10, 3)) * 0.1, rng.normal(size=(10, 3)))


class OneMode:
    """One elastic mode at 300 Hz, a smooth bending field: what the virtual test needs of FE modes."""

    omega = 2 * np.pi * np.array([300.0])

    def shapes_at(self, points: np.ndarray) -> np.ndarray:
        return np.stack([np.zeros(len(points)), np.zeros(len(points)), 30.0 * points[:, 0] ** 2], axis=1)[None]

    def nearest(self, points: np.ndarray) -> np.ndarray:
        return points


def argument(cls) -> str:
    """A sample ``--effect`` argument: on line 3 (exciter 2), a swap of 3 and 8, at 50 Hz (a frequency effect)."""
    where = "3,8" if cls.lines_needed == 2 else "2" if cls.perturbs == "exciter" else "3"
    where = f"{MAINS_HZ:g}" if cls.place == "frequency" else where
    return f"{cls.name}@{where}" if cls.discrete else f"{cls.name}={SAMPLE[cls.unit]}@{where}"


def place(cls) -> tuple[int, ...]:
    """The 0-based lines of ``argument`` (every sensor for a frequency effect)."""
    if cls.place == "frequency":
        return tuple(range(10))
    return (2, 7) if cls.lines_needed == 2 else (1,) if cls.perturbs == "exciter" else (2,)


def recorded(body, sensors, cls=None, **changes):
    """The exact virtual test of ``body`` (free, rigid unless ``modes``) with ``cls``'s sample effect."""
    effects = () if cls is None or not cls.simulated else (parse_effect(argument(cls)),)
    return run(body, sensors, structure_exciters(), effects=effects, setup=EXACT, seed=1, **changes)


def test_the_registry_is_well_formed():
    names = [cls.name for cls in EFFECTS]
    assert len(set(names)) == len(names) and set(BY_NAME) == set(names)
    for cls in EFFECTS:
        assert cls.kind in KINDS and cls.perturbs in PERTURBS and cls.summary
        assert cls.__module__ == f"massline.identify.diagnose.effects.{cls.name}"  # one module per effect
        assert cls.discrete or cls.unit, cls.name  # a size has a unit
        assert cls.simulated == (cls.perturbs in ("sensor", "exciter"))  # else the support or the modes
        assert cls.model in ("block", "discrete", "tail", "mass", "gauge", "lines", "row", None)
        assert (cls.undone_on == "identify") == (cls.identify_option is not None)  # identify takes it as an option
        assert cls.place in ("lines", "frequency")


@pytest.mark.parametrize("cls", EFFECTS, ids=lambda c: c.name)
def test_every_effect_is_simulated(cls, body, sensors):
    """A virtual test with the effect differs from the same test without it."""
    if cls.perturbs == "support":
        cord = Suspension(cords=(Cord(body.cog + [0.0, 0.0, 0.05], body.mass * (2 * np.pi * 5.0) ** 2, 0.3),))
        clean, _ = recorded(body, sensors)
        rec, _ = recorded(body, sensors, suspension=cord)
    elif cls.perturbs == "modes":
        clean, _ = recorded(body, sensors)
        rec, _ = recorded(body, sensors, modes=OneMode())
    else:
        clean, _ = recorded(body, sensors)
        rec, truth = recorded(body, sensors, cls)
        assert [e["effect"] for e in truth["effects"]] == [cls.name]
        assert truth["effects"][0]["lines"] == [t + 1 for t in place(cls)]
    change = np.abs(rec.frf - clean.frf).max() / np.abs(clean.frf).max()
    assert change > 1e-3, f"{cls.name} changes the test by {change:.1e} only"


def test_every_simulated_effect_is_documented_in_simulate_help(capsys):
    assert run_cli(["simulate", "--help"], show_warnings=True) == 0
    out = " ".join(capsys.readouterr().out.split())  # argparse wraps the help
    assert " ".join(effect_help().split()) in out
    for cls in EFFECTS:
        assert (cls.name in effect_help()) == cls.simulated, cls.name
    for cls in simulated():
        assert parse_effect(argument(cls)).name == cls.name  # its syntax parses


def misfit(result) -> float:
    """χ² beyond the data's own scatter about each FRF's massline (the noise's share of χ²)."""
    return result.chi2 - float(np.sum(result.problem.data.rss / result.problem.sigma**2))


def block_finding(cls, body, sensors) -> tuple[Finding, object]:
    """The effect's block fitted to exact masslines with the effect: the model explains them."""
    rec, _ = recorded(body, sensors, cls)
    layout = Layout.of(rec.sensors, rec.exciters, False)
    assert cls.blocks(layout) and set(cls.blocks(layout)) <= set(layout.candidates())
    band = BandData.from_recording(rec.frequencies, rec.frf, 5.0, 95.0)
    start = base_fit(band, layout, frozenset(), 0.01 if cls.widens_prior else 0.0)  # a tilt widens a datasheet's
    block = Block(cls.name, place(cls)[0])
    found = fit(start.problem, (block,), start)
    assert misfit(found) < 1e-2 * misfit(start) and plausible(found, block)
    assert cls.widens_prior or cls.values(layout, block.target) > 0  # parameters, or a released prior
    return accepted_finding(found, band, block, {"chi2_drop": misfit(start) - misfit(found)}), rec


def discrete_finding(cls, body, sensors) -> tuple[Finding, object]:
    """The rigid-subspace screen proposes undoing the effect where it was concealed, first."""
    rec, _ = recorded(body, sensors, cls)
    A = rec.frf[:, :, 10].real
    best = discrete_fixes(A, kinematic_matrix(rec.sensors, False))[0]
    assert best[1:] == (cls.name, place(cls))
    return Finding(cls.name, place(cls), None, {}, {"delta_bic": 100.0}), rec


def tail_finding(cls, body, sensors) -> tuple[Finding, object]:
    """The tail law of the effect, fitted on a band with its mode outside."""
    assert cls.name in TAIL_LAWS
    if cls.perturbs == "support":
        cord = Suspension(cords=(Cord(body.cog + [0.0, 0.0, 0.05], body.mass * (2 * np.pi * 5.0) ** 2, 0.3),))
        rec, _ = recorded(body, sensors, suspension=cord)
    else:
        rec, _ = recorded(body, sensors, modes=OneMode())
    band = BandData.from_recording(rec.frequencies, rec.frf, 10.0, 95.0)
    layout = Layout.of(rec.sensors, rec.exciters, False)
    start = base_fit(band, layout, frozenset(), 0.0)
    law = refit(start, band, frozenset({cls.name}), ())
    assert misfit(law) < 0.2 * misfit(start)  # one mode's law for a cord's six: most of the tail
    return accepted_finding(law, band, cls.name, {"chi2_drop": misfit(start) - misfit(law)}, {cls.name: np.nan}), rec


def mass_finding(cls, body, sensors) -> tuple[Finding, object]:
    """A mass at one accelerometer, weighed against the mesh's body from θ̂ − θ_mesh."""
    rec, _ = recorded(body, sensors, cls)
    theta = RigidModel(body, False).theta + point_mass_theta(SAMPLE["kg"], sensors.points[2])
    loading = mass_loading(theta, np.diag((1e-6 * np.abs(theta) + 1e-9) ** 2), False, sensors, body)
    assert loading is not None and loading.housings.alike_mass == pytest.approx(SAMPLE["kg"])
    return loading.finding(), rec


def gauge_finding(cls, body, sensors) -> tuple[Finding, object]:
    """A mass riding at every drive point, found in the masslines by profiling identify's estimator over it (exact
    axes: ten uniaxials and three hits leave no redundancy beside their transverse readings)."""
    mass = SAMPLE["kg"] / 5
    effect = parse_effect(f"{cls.name}={mass}@all")
    rec, _ = run(body, sensors, structure_exciters(), effects=(effect,), setup=EXACT, seed=1)
    found = identify_recording(rec, None, 0.0, draws=0)
    gauge = gauge_mass(found.data, found.sigma, False, 0.0, found.best)
    assert gauge is not None and gauge.mass == pytest.approx(mass, rel=1e-3)
    option = {cls.identify_option: cls.option_value(gauge.finding())}
    assert identify_recording(rec, None, 0.0, draws=0, **option).best.chi2 < 1e-3 * found.best.chi2
    return gauge.finding(), rec


def lines_finding(cls, body, sensors) -> tuple[Finding, object]:
    """Its lines found in a noisy record (1 %): the fundamental at the place given, set aside."""
    setup = Acquisition(400.0, 800, Noise(0.01, 0.0), dc_line=False)
    rec, _ = run(body, sensors, structure_exciters(), effects=(parse_effect(argument(cls)),), setup=setup, seed=1)
    found = find_mains(rec.frequencies, rec.frf)
    assert found is not None and abs(found.fundamental - MAINS_HZ) < 0.5 and 1 in found.harmonics
    assert found.amplitudes[0] == pytest.approx(SAMPLE[cls.unit], rel=0.2)
    kept = rec.kept(~found.aside)
    assert find_mains(kept.frequencies, kept.frf) is None  # nothing stands out once its lines are set aside
    return mains_finding(found), rec


def row_finding(cls, body, sensors) -> tuple[Finding, object]:
    """Its factor of frequency fitted on the band's lines of every channel's row: named first at its channel, its
    size recovered."""
    rec, _ = recorded(body, sensors, cls)
    band = BandData.from_recording(rec.frequencies, rec.frf, 5.0, 95.0)
    found, _ = row_findings(band, Layout.of(rec.sensors, rec.exciters, False))
    assert found and (found[0].effect, found[0].channels) == (cls.name, place(cls))
    assert found[0].parameters[cls.parameter] == pytest.approx(SAMPLE[cls.unit], rel=1e-3)
    return found[0], rec


FINDINGS = {
    "block": block_finding,
    "discrete": discrete_finding,
    "tail": tail_finding,
    "mass": mass_finding,
    "gauge": gauge_finding,
    "lines": lines_finding,
    "row": row_finding,
}


@pytest.mark.parametrize("cls", EFFECTS, ids=lambda c: c.name)
def test_every_effect_is_diagnosed_described_and_in_the_json(cls, body, sensors):
    """Its model in the diagnosis has parameters (or it is knowingly not diagnosed), its finding's sentence
    renders, and the finding round-trips through the diagnose JSON with its name and kind."""
    if cls.model is None:  # knowingly not diagnosed: it has no block, no screen, no tail, no loading
        assert not cls.blocks(Layout.of(sensors, structure_exciters(), False)) and not cls.proposals(10)
        assert cls.name not in TAIL_LAWS
        return
    finding, rec = FINDINGS[cls.model](cls, body, sensors)
    assert finding.effect == cls.name and finding.kind == cls.kind
    note = finding_note(finding, rec.sensor_channels, rec.exciter_channels)
    assert note and "{" not in note and "None" not in note
    payload = json.loads(to_json(finding_payload(finding, rec)))
    assert (payload["effect"], payload["kind"]) == (cls.name, cls.kind)
    assert (payload["sensor"] is None) == (not finding.channels)


@pytest.mark.parametrize("name", [f for f in FAULTS if f in BY_NAME])
def test_every_blind_fault_is_described_as_concealed(name):
    """The demo's words for each fault the blind scenarios conceal (its size drawn as they draw it)."""
    cls = BY_NAME[name]
    size = None if cls.discrete else cls.blind_size(np.random.default_rng(0), 4.0, (10.0, 200.0))
    text = cls.concealed(size, Scene("12:+X", ("12:+X", "14:+Y"), "3:-Z", (10.0, 200.0)))
    assert text and "{" not in text and "None" not in text


def test_the_virtual_test_is_handed_effects_and_never_imports_the_registry():
    """DESIGN.md's layers: virtual/ imports only core, meshes and uff; the effects reach it as objects."""
    import ast
    from pathlib import Path

    import massline.virtual

    for path in Path(massline.virtual.__file__).parent.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            names += [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            assert not any(n.startswith(("massline.identify", "massline.placement")) for n in names), path.name
