"""Diagnosis: the band reduction, the effect model, the discrete screen and the command."""

import json

import numpy as np
import pytest
from conftest import bundled
from test_cli import massline
from test_uff_reader import assert_command_refuses

from massline.identify.diagnose.diagnosis import diagnose
from massline.identify.diagnose.effect_fit import base_fit
from massline.identify.diagnose.effect_fit import fit
from massline.identify.diagnose.effect_model import Block, Layout, line_coordinates
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.estimator import DIVERGED
from massline.identify.warning_codes import codes_of
from massline.identify.diagnose.screens import discrete_fixes, kinematic_matrix, screen
from massline.identify.pipeline import identify_recording
from massline.identify.sensor_mass import point_mass_theta
from massline.identify.tails import BandData
from massline.core.errors import MasslineError
from massline.core.files import to_json
from massline.placement.hand_layouts import plate_table1, structure_exciters
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.writer import write_uff
from massline.identify.diagnose.effects import parse_effect
from massline.virtual.measurement import Noise
from massline.virtual.acquisition import Acquisition, run


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def test_tail_reduction_recovers_the_massline_and_its_parabola():
    """One support mode (8 Hz) and one elastic mode (900 Hz) with per-FRF amplitudes: masslines to 1e-9."""
    f = np.linspace(20.0, 200.0, 300)
    w = 2 * np.pi * f
    ws, wr = 2 * np.pi * 8.0, 2 * np.pi * 900.0
    A = np.array([[0.3, -0.1], [0.05, 0.2]])
    b = np.array([[2000.0, -500.0], [300.0, 800.0]])
    c = np.array([[-0.02, 0.01], [0.005, -0.03]])
    H = A[:, :, None] + b[:, :, None] / (w**2 - ws**2) + c[:, :, None] * w**2 / (wr**2 - w**2)
    band = BandData(f, H.astype(complex))
    full = band.reduced(frozenset({"suspension", "residual_flexibility"}))
    np.testing.assert_allclose(full.massline, A, rtol=1e-9)
    assert band.pole_hz(full, "suspension") == pytest.approx(8.0, rel=1e-6)
    assert band.pole_hz(full, "residual_flexibility") == pytest.approx(900.0, rel=1e-4)
    plain = band.reduced(frozenset())
    assert np.abs(plain.massline - A).max() > 1e-3  # without the tails the average is off
    trial = A + 0.01  # RSS(A) = rss + κ(A − â)² is the direct residual of a constant
    direct = np.sum(np.abs(H - trial[:, :, None]) ** 2, axis=2)
    np.testing.assert_allclose(plain.rss_at(trial), direct, rtol=1e-9)


def _band(recording, low=5.0, high=95.0):
    return BandData.from_recording(recording.frequencies, recording.frf, low, high)


@pytest.mark.parametrize(
    "effect, block",
    [
        ("sensor_gain=0.2@5", Block("sensor_gain", 4)),
        ("sensor_location=0.01@3", Block("sensor_location", 2)),
        ("excitation_direction=10@2", Block("excitation_direction", 1)),
        ("excitation_location=0.01@3", Block("excitation_location", 2)),
    ],
)
def test_effect_model_recovers_an_effect_exactly(structure, effect, block):
    """Masslines with 1e-8 noise of a layout with one effect: the model with that block reproduces them."""
    rng = np.random.default_rng(2)
    sensors = Lines(rng.normal(size=(10, 3)) * 0.1, rng.normal(size=(10, 3)))
    setup = Acquisition(100.0, 100, Noise(1e-8, 0))
    rec, truth = run(structure, sensors, structure_exciters(), effects=(parse_effect(effect),), setup=setup, seed=3)
    layout = Layout.of(rec.sensors, rec.exciters, False)
    start = base_fit(_band(rec), layout, frozenset(), 0.0)
    found = fit(start.problem, (block,), start)
    assert found.body.mass == pytest.approx(structure.mass, rel=1e-7)
    np.testing.assert_allclose(
        found.body.inertia_cog, structure.inertia_cog, atol=1e-7 * structure.principal_moments[2]
    )
    assert start.chi2 > 1e4 * found.chi2


def test_discrete_screen_names_a_flip_and_a_swap(structure):
    rng = np.random.default_rng(0)
    sensors = Lines(rng.normal(size=(10, 3)) * 0.1, rng.normal(size=(10, 3)))
    A = synthesise(structure, sensors, structure_exciters()).values
    S = kinematic_matrix(sensors, False)
    flipped = A.copy()
    flipped[3] *= -1
    assert discrete_fixes(flipped, S)[0][1:] == ("sensor_polarity", (3,))
    swapped = A.copy()
    swapped[[2, 7]] = swapped[[7, 2]]
    assert discrete_fixes(swapped, S)[0][1:] == ("channel_swap", (2, 7))


def test_point_mass_vector_is_the_parameters_of_a_point_mass():
    p = np.array([0.1, -0.2, 0.3])
    heavy = RigidBody(2.0, np.zeros(3), np.diag([1.0, 2.0, 3.0]))
    loaded_theta = heavy.theta + point_mass_theta(0.5, p)
    m, c = 2.5, 0.5 * p / 2.5
    assert RigidBody.from_theta(loaded_theta).mass == pytest.approx(m)
    np.testing.assert_allclose(RigidBody.from_theta(loaded_theta).cog, c, atol=1e-15)


def twelve_lines():
    """Twelve accelerometer lines around the structure: room to check each against the others."""
    rng = np.random.default_rng(4)
    return Lines(rng.normal(size=(12, 3)) * 0.1, rng.normal(size=(12, 3)))


def test_clean_test_has_no_fault_and_after_is_identify(structure):
    """No fault: nothing to undo, so the properties after are identify's, the same as before, and identify's
    result on the file is what diagnose reports before (one estimator)."""
    rec, _ = run(structure, twelve_lines(), structure_exciters(), setup=Acquisition(100.0, 400), seed=1)
    found = diagnose_recording(rec, None, structure)
    assert [f for f in found.findings if f.kind == "fault"] == []
    assert found.result.relative_rms("after") < 1.1 * found.result.noise
    properties = found.document["properties"]
    assert to_json(properties["after"]) == to_json(properties["before"])
    assert to_json(properties["before"]) == to_json(identify_recording(rec).payload)


def test_identify_and_diagnose_json_say_their_units(structure):
    """DESIGN.md's ``units`` block in identify's JSON and in diagnose's, beside the numbers it governs."""
    rec, _ = run(structure, twelve_lines(), structure_exciters(), setup=Acquisition(100.0, 400), seed=2)
    units = {"mass": "kg", "length": "m", "inertia": "kg m^2", "frequency": "Hz"}
    found = diagnose_recording(rec, None, structure)
    assert found.document["units"] == units and found.document["properties"]["before"]["units"] == units


def test_diagnose_checks_the_mesh_as_identify_does(structure):
    """A mesh of another body: diagnose's "before" carries identify --mesh's mismatch warning, in its
    warnings and in the JSON, where before it said nothing (the bracket's 0.35 kg against the 4 kg structure)."""
    rec, _ = run(structure, twelve_lines(), structure_exciters(), setup=Acquisition(100.0, 400), seed=2)
    found = diagnose_recording(rec, None, bundled("bracket").nominal)
    assert "nominal_mass_mismatch" in codes_of(found.before.warnings)
    [warned] = [w for w in found.document["warnings"] if w["code"] == "nominal_mass_mismatch"]
    assert "mesh's nominal" in warned["text"]


def test_diagnose_command_finds_a_flipped_sensor_and_writes_the_json(structure, tmp_path):
    effects = (parse_effect("sensor_polarity@4"),)
    rec, _ = run(structure, twelve_lines(), structure_exciters(), effects=effects, setup=Acquisition(100.0, 400))
    path = tmp_path / "flip.uff"
    write_uff(path, rec)
    out, png = tmp_path / "d.json", tmp_path / "d.png"
    result = massline("diagnose", path, "--band", "5", "95", "--mesh", "structure", "--json", out, "--plot", png)
    assert result.returncode == 0, result.stderr
    assert "polarity flipped" in result.stdout
    found = json.loads(out.read_text())
    first = found["findings"][0]
    assert first["effect"] == "sensor_polarity" and first["sensor"]["node"] is not None
    assert found["fit"]["after"] < 1.5 * found["fit"]["noise"] < found["fit"]["before"]
    assert found["properties"]["after"]["mass"] == pytest.approx(structure.mass, rel=0.003)
    node, code = to_recording(read_uff(path)).sensor_labels[3]
    assert first["sensor"] == {"node": node, "dir": code}
    assert png.read_bytes()[:4] == b"\x89PNG"
    again = massline("diagnose", path, "--band", "5", "95", "--json", out)
    assert again.returncode == 2 and "--force" in again.stderr


@pytest.mark.parametrize("case", ["truncated ascii", "NaN"])  # the reader is identify's, tested there
def test_diagnose_command_refuses_bad_files_in_one_line(tmp_path, case):
    assert_command_refuses("diagnose", tmp_path, case)


def test_diagnose_command_refuses_a_missing_mesh_and_a_band_outside_the_record(structure, tmp_path):
    rec, _ = run(structure, twelve_lines(), structure_exciters(), setup=Acquisition(100.0, 400))
    path = tmp_path / "clean.uff"
    write_uff(path, rec)
    for extra in (["--mesh", str(tmp_path / "nowhere.stl"), "--units", "mm"], ["--band", "150", "180"]):
        result = massline("diagnose", path, *extra)
        assert result.returncode == 2 and result.stderr.count("\n") == 1 and "Traceback" not in result.stderr


@pytest.mark.parametrize(
    "effect, channels, exciter",
    [("sensor_polarity@3", (2,), None), ("sensor_gain=0.2@5", (4,), None), ("excitation_location=0.02@1", (), 0)],
)
def test_plate_data_are_diagnosed_with_the_planar_model(effect, channels, exciter):
    """Eight out-of-plane accelerometers on the paper's plate, its three hits: the plate's 6 parameters."""
    plate = bundled("plate").nominal
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(-0.2, 0.2, 8), rng.uniform(-0.15, 0.15, 8), np.zeros(8)])
    sensors = Lines(points + plate.cog * [1, 1, 0], np.tile([0, 0, 1.0], (8, 1)))
    rec, _ = run(plate, sensors, plate_table1()[1], effects=(parse_effect(effect),), setup=Acquisition(100.0, 400))
    found = diagnose_recording(rec, None, plate)
    first = found.findings[0]
    assert first.kind == "fault"
    assert (first.effect, first.channels, first.exciter) == (effect.split("=")[0].split("@")[0], channels, exciter)
    assert found.after_body.mass == pytest.approx(plate.mass, rel=0.003)


def test_every_housing_on_a_plate_is_weighed_in_its_six_parameters_and_taken_off():
    """5 g on each of the plate's eight out-of-plane accelerometers (40 g on the paper's 0.567 kg plate):
    the loading of every housing is named, weighed within 3σ and taken off the properties after."""
    plate = bundled("plate").nominal
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(-0.2, 0.2, 8), rng.uniform(-0.15, 0.15, 8), np.zeros(8)])
    sensors = Lines(points + plate.cog * [1, 1, 0], np.tile([0, 0, 1.0], (8, 1)))
    rec, _ = run(plate, sensors, plate_table1()[1], setup=Acquisition(100.0, 400, sensor_mass=0.005))
    found = diagnose_recording(rec, None, plate)
    loading = next(f for f in found.findings if f.effect == "sensor_mass_loading")
    assert loading.parameters["every_housing"] and loading.parameters["housings"] == 8
    assert abs(loading.parameters["mass_kg"] - 0.005) < 3 * loading.parameters["mass_std_kg"]
    assert found.after_body.mass == pytest.approx(plate.mass, rel=3e-4)
    assert found.before.best.body.mass == pytest.approx(plate.mass + 0.04, rel=3e-4)


def test_screens_without_a_model_locate_a_flipped_channel_and_an_extra_mode(structure):
    """Fourteen sensors, eight hits. A flipped channel keeps the matrix rank 6 (σ₇/σ₁ at the noise) but breaks the
    leave-one-out prediction of that channel (misfit 2: it reads minus what the others predict); a seventh,
    non-rigid motion (a loose part) lifts σ₇/σ₁."""
    rng = np.random.default_rng(0)
    sensors = Lines(rng.normal(size=(14, 3)) * 0.1, rng.normal(size=(14, 3)))
    exciters = Lines(rng.normal(size=(8, 3)) * 0.1, rng.normal(size=(8, 3)))
    A = synthesise(structure, sensors, exciters).values
    f = np.linspace(10.0, 100.0, 50)
    layout = Layout.of(sensors, exciters, False)
    noisy = A[:, :, None] * (1 + 1e-3 * rng.normal(size=(14, 8, 50)))
    flipped = noisy.copy()
    flipped[4] *= -1
    loose = noisy + 0.05 * np.abs(A).max() * np.outer(rng.normal(size=14), rng.normal(size=8))[:, :, None]
    clean, flip, part = (screen(BandData(f, H.astype(complex)), layout) for H in (noisy, flipped, loose))
    assert np.median(clean["seventh_singular_value"]) < 3e-3 and np.median(flip["seventh_singular_value"]) < 3e-3
    assert flip["channel_consistency"][4] == pytest.approx(2.0, abs=0.05)  # its reading against the others': −1×
    assert max(clean["channel_consistency"]) < 0.05
    assert np.median(part["seventh_singular_value"]) > 0.01


def test_a_gain_cannot_hide_in_a_stiff_support_shared_by_the_rigid_body(structure):
    """A rigid body on one stiff spring (exact FRFs S'(M − K/ω²)⁻¹Wᵀ, support mode at half the band's lower edge,
    1e-4 noise) with channel 4 reading 12 % low: named at its channel with the support's tail s_iᵀ X e_j shared
    by every FRF, and X = M⁻¹KM⁻¹/ω_mid² on the hits' lines (the 1/ω² term, exact with the pole for one spring)."""
    rng = np.random.default_rng(5)
    layout = Layout.of(twelve_lines(), structure_exciters(), False)
    S = line_coordinates(layout.sensors.points, layout.sensors.directions, False)
    E = line_coordinates(layout.exciters.points, layout.exciters.directions, False)
    M = RigidModel(structure, False).mass_matrix(structure.theta)
    cord = line_coordinates((structure.cog + [0.0, 0.0, 0.2])[None], np.array([[0.0, 0.0, 1.0]]), False)[0]
    K = 2 * np.outer(cord, cord) * (2 * np.pi * 20.0) ** 2 / (cord @ np.linalg.solve(M, cord))
    f = np.linspace(40.0, 60.0, 200)
    w = 2 * np.pi * f
    H = np.einsum("ia,fab,jb->ijf", S, np.linalg.inv(M[None] - K[None] / w[:, None, None] ** 2), E)
    H[3] *= 0.88
    H = H * (1 + 1e-4 * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape)))
    found = diagnose(BandData(f, H.astype(complex)), layout)
    fault = [x for x in found.findings if x.kind == "fault"][0]
    assert (fault.effect, fault.channels) == ("sensor_gain", (3,))
    assert fault.parameters["gain"] == pytest.approx(0.88, abs=0.005)
    assert found.after.problem.data.shared
    X = np.linalg.solve(M, np.linalg.solve(M, K).T) / (w[0] * w[-1])  # four hits see X on their four lines
    np.testing.assert_allclose(found.after.support_matrix @ E.T, X @ E.T, atol=1e-3 * np.abs(X @ E.T).max())


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_a_plate_sensor_off_its_label_is_not_taken_for_a_swap(tmp_path, seed):
    """The blind plate's sensor moved on its face: a swap with a neighbour halves the misfit, but the moved
    accelerometer explains it better, and is named (both seeds were named channel_swap before)."""
    from test_diagnose_blind import CYCLE, bench, blind_case

    row = blind_case(bench("plate"), "sensor_location", seed, CYCLE[seed], tmp_path)
    assert row["right"] and "channel_swap" not in row["named"], row["named"]


def test_the_fits_covariance_survives_columns_of_every_scale():
    """(JᵀJ)⁻¹ for columns scaled from 1e-6 to 1e8 (θ̃ beside a stiff support's X): positive, and the inverse
    of the well-conditioned unscaled problem scaled back, where forming JᵀJ loses it."""
    from massline.identify.diagnose.effect_fit import unscaled_covariance

    rng = np.random.default_rng(2)
    J0 = rng.normal(size=(400, 12))
    scales = np.logspace(-6, 8, 12)
    covariance = unscaled_covariance(J0 * scales)
    expected = np.linalg.inv(J0.T @ J0) / np.outer(scales, scales)
    np.testing.assert_allclose(covariance, expected, rtol=1e-8)
    assert (np.diag(covariance) > 0).all()


def test_drive_points_that_cannot_be_weighed_leave_the_housings_weighed(structure, monkeypatch):
    """The bracket's default plan, a faulty channel: the fit with gauges riding at the drive points diverged and
    diagnose crashed (blind table, seeds 0–9). Now the drive points are not weighed and the diagnosis goes on."""
    import massline.identify.diagnose.against_mesh as against_mesh

    tried = []

    def diverges(*args, **kwargs):
        tried.append(True)
        raise MasslineError(DIVERGED)

    monkeypatch.setattr(against_mesh, "gauge_pattern", diverges)
    rec, _ = run(structure, twelve_lines(), structure_exciters(), setup=Acquisition(100.0, 400), seed=1)
    found = diagnose_recording(rec, None, structure)
    assert tried and [f for f in found.findings if f.kind == "fault"] == [] and found.after is not None


def test_the_one_criterion_states_its_false_alarm_rate():
    """``EVIDENCE``: on noise alone a χ² drops by more than it for one added value with probability 0.16 %
    (docs/diagnosing.md, criterion.py), for two values 0.67 %, for three 1.9 %."""
    from scipy.stats import chi2

    from massline.identify.diagnose.criterion import EVIDENCE

    assert [round(100 * chi2.sf(EVIDENCE, k), 2) for k in (1, 2, 3)] == [0.16, 0.67, 1.86]
