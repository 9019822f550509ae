"""Housings that are not all alike: triaxials of 25 g beside uniaxials of 8 g.

``--sensor-mass 0.008 1=0.025 2=0.025`` (the default, then per point label, the file's nodes) in simulate and
identify: the bare body inside the bounds; with the mesh and no masses given, the diagnosis weighs each housing
(non-negative, with its ±) from the body's excess over the mesh and names the loaded ones.
"""

import json

import numpy as np
import pytest
from conftest import bundled

from massline import plan_layout
from massline.cli.app import run as run_cli
from massline.core.errors import MasslineError
from massline.core.housing_masses import HousingMasses
from massline.core.numbering import point_labels
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import identify_recording
from massline.placement.hand_layouts import bracket_exciters, bracket_sensors
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise

BOUND = 0.3  # %: the lab matrix's bound on the mass


def test_the_default_comes_first_then_each_point_that_differs():
    masses = HousingMasses.parse(["0.004", "1=0.025", "2=0.025"])
    assert masses.default == 0.004 and masses.by_label == {1: 0.025, 2: 0.025}
    np.testing.assert_array_equal(masses.of([1, 2, 3]), [0.025, 0.025, 0.004])
    assert HousingMasses.parse(0.01).of([7]) == [0.01] and not HousingMasses.parse(["0"]).any
    assert masses.describe() == "4 g each, 25 g at points 1, 2"


@pytest.mark.parametrize("tokens", [["-1"], ["nan"], ["0.004", "x=1"], ["1=0.02", "0.004"], ["0.004", "2=-0.01"]])
def test_bad_masses_are_refused(tokens):
    with pytest.raises(MasslineError, match="sensor_mass"):
        HousingMasses.parse(tokens)


def test_a_label_the_test_does_not_have_is_refused():
    with pytest.raises(MasslineError, match="no accelerometer is at point 99"):
        HousingMasses.parse(["0.008", "99=0.025"]).check_labels([1, 2, 3])


@pytest.fixture(scope="module", params=["bracket", "structure"])
def mixed(request):
    """A rigid body's test with two 25 g housings (the first two points) and 8 g ones elsewhere, 1 % noise."""
    body = bundled(request.param)
    plan = plan_layout(body)
    first, second = sorted(set(point_labels(plan.sensors, plan.exciters)[0].tolist()))[:2]
    masses = HousingMasses(0.008, {first: 0.025, second: 0.025})
    setup = Acquisition(noise=Noise(0.01, 0.0), sensor_mass=masses, dc_line=False)
    recording, truth = run(body.nominal, plan.sensors, plan.exciters, None, None, (), setup, seed=1)
    return request.param, body, masses, recording


def test_identify_with_each_housing_is_inside_the_bounds(mixed):
    name, body, masses, recording = mixed
    found = identify_recording(recording, draws=20, sensor_mass=masses)
    error = 100 * abs(found.body.mass / body.nominal.mass - 1)
    assert error < BOUND, (name, error)
    assert found.payload["sensor_mass"] == {str(k): masses.of([k])[0] for k in found.housings.labels}
    alike = identify_recording(recording, draws=0, sensor_mass=masses.default)
    assert 100 * abs(alike.body.mass / body.nominal.mass - 1) > BOUND  # one mass for all is not enough


def test_housings_sit_at_the_points_the_files_node_labels_name(bracket, tmp_path):
    """The bracket's hand layout (six uniaxials, one per point) with 25 g housings at points 1 and 2 and 8 g
    elsewhere, 1 % noise, written as a Universal File and read back: each housing is placed at the node its label
    names, and the bare body's CoG and principal moments are the mesh's within 3σ (the information's 1-σ, scaled by
    χ²; a bootstrap gives the same here). Each label's housing taken off one point along moves the CoG by 3.4 mm,
    hundreds of σ. Recordings simulated in memory carry no node labels: their housings are placed by point."""
    masses = HousingMasses(0.008, {1: 0.025, 2: 0.025})
    setup = Acquisition(noise=Noise(0.01, 0.0), sensor_mass=masses, dc_line=False)
    recording, _ = run(bracket, bracket_sensors(), bracket_exciters(), None, None, (), setup, seed=1)
    write_uff(tmp_path / "bracket.uff", recording)
    found = identify_recording(tmp_path / "bracket.uff", draws=0, sensor_mass=masses)
    assert found.recording.sensor_labels is not None  # the file's nodes: Housings.on places by label
    np.testing.assert_array_equal(found.housings.labels, [1, 2, 3, 4, 5, 6])
    np.testing.assert_allclose(found.housings.points, bracket_sensors().points, atol=1e-9)
    cog = (found.body.cog - bracket.cog) / found.std["cog"]
    moments = (found.body.principal_moments - bracket.principal_moments) / found.std["principal_moments"]
    z = np.concatenate([cog, moments])
    assert np.abs(z).max() < 3, z


def test_the_mesh_names_the_loaded_housings(mixed):
    name, body, masses, recording = mixed
    run_ = diagnose_recording(recording, None, body.nominal)
    faults = [f for f in run_.findings if f.kind == "fault"]
    assert [f.effect for f in faults] == ["sensor_mass_loading"], (name, faults)
    found = faults[0].parameters
    assert found["each_housing"] and min(found["masses_kg"]) >= 0
    labels = point_labels(recording.sensors, recording.exciters)[0]
    heavy_points = recording.sensors.points[[int(np.flatnonzero(labels == k)[0]) for k in masses.by_label]]
    two = np.argsort(found["masses_kg"])[-2:]  # the two heaviest found are the two 25 g housings
    found_points = np.array(found["points_m"])[two]
    assert np.allclose(np.sort(found_points, axis=0), np.sort(heavy_points, axis=0), atol=1e-6), name
    assert sum(found["masses_kg"]) == pytest.approx(0.05 + 0.008 * (len(set(labels)) - 2), rel=0.05)
    assert 100 * abs(run_.after_body.mass / body.nominal.mass - 1) < BOUND, name


def test_unknown_labels_are_refused_on_the_command_line(tmp_path, capsys):
    plan = tmp_path / "plan"
    assert run_cli(["plan", "plate", "--minimal", "--out", str(plan)]) == 0
    capsys.readouterr()  # the plan's progress lines
    code = run_cli(["simulate", str(plan / "plan.json"), "--rigid", "--sensor-mass", "0.008", "99=0.025",
                    "--out", str(tmp_path / "t.uff")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "no accelerometer is at point 99" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "t.uff").exists()
    assert run_cli(["simulate", str(plan / "plan.json"), "--rigid", "--out", str(tmp_path / "t.uff")]) == 0
    capsys.readouterr()
    assert run_cli(["identify", str(tmp_path / "t.uff"), "--sensor-mass", "0.008", "99=0.02"]) == 2
    assert "no accelerometer is at point 99" in capsys.readouterr().err


FIXED = ["--fixed-sensor", "-0.009087", "0.011157", "0.054492", "0.5691", "0.5774", "0.5855"]  # on the bracket


def test_the_plan_states_the_housings_loading_and_simulate_puts_them_on(tmp_path, capsys):
    """``plan --sensor-mass 0.008 1=0.025`` (point 1 the fixed sensor's): plan.json's ``loading`` is the tested body's
    change from the bare one, exactly (θ_tested = θ_bare + Σ m_k φ(r_k)), the console says it with the option
    that takes it off, and ``simulate`` without --sensor-mass puts the plan's housings on."""
    plan = tmp_path / "plan"
    given = ["--sensor-mass", "0.008", "1=0.025"]
    assert run_cli(["plan", "bracket", "--minimal", *FIXED, *given, "--out", str(plan)]) == 0
    assert "identify --sensor-mass 0.008 1=0.025 takes them off" in capsys.readouterr().out.replace("\n", " ")
    doc = json.loads((plan / "plan.json").read_text())
    found, body = doc["loading"], bundled("bracket").nominal
    sensors = np.array([s["point"] for s in doc["sensors"]])
    points, first = np.unique(np.array([s["node"] for s in doc["sensors"]]), return_index=True)
    masses = np.where(points == 1, 0.025, 0.008)
    assert found["housings"] == len(points) and found["total_kg"] == pytest.approx(masses.sum(), rel=1e-12)
    assert found["mass_percent"] == pytest.approx(100 * masses.sum() / body.mass, rel=1e-9)
    cog = (body.mass * body.cog + masses @ sensors[first]) / (body.mass + masses.sum())
    assert found["cog_shift_mm"] == pytest.approx(1e3 * np.linalg.norm(cog - body.cog), rel=1e-9)
    assert found["in_predicted_std"]["mass"] == pytest.approx(masses.sum() / doc["predicted_std"]["mass"], rel=1e-9)
    out = tmp_path / "t.uff"
    assert run_cli(["simulate", str(plan / "plan.json"), "--rigid", "--out", str(out)]) == 0
    truth = json.loads(out.with_suffix(".truth.json").read_text())
    assert truth["sensor_mass"] == {"default": 0.008, "by_point": {"1": 0.025}}


@pytest.mark.parametrize("fixed", [FIXED, []])
def test_the_plan_refuses_a_point_no_fixed_sensor_has_before_any_work(tmp_path, capsys, fixed):
    plan = tmp_path / "plan"
    code = run_cli(["plan", "bracket", "--minimal", *fixed, "--sensor-mass", "0.008", "2=0.025", "--out", str(plan)])
    err = capsys.readouterr().err
    assert code == 2 and "--sensor-mass 2=…" in err and len(err.strip().splitlines()) == 1
    assert not (plan / "plan.json").exists()
