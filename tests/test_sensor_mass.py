"""Accelerometer housings taken off the body as tested (--sensor-mass) and a scale's reading as a prior
(--weighed-mass): exact algebra, the virtual test, and the command line."""

import json
import re
from dataclasses import replace

import numpy as np
import pytest
import session_cache
from conftest import assert_body_close, bundled
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation
from test_cli import cli, massline

from massline.core.calibration import Calibration
from massline.identify.estimator import estimate
from massline.identify.pipeline import identify_recording
from massline.identify.sensor_mass import Housings, housing_points, point_mass_theta
from massline.identify.uncertainty import bootstrap
from massline.identify.warning_codes import codes_of
from massline.identify.weighing import WeighedMass
from massline.core.errors import MasslineError
from massline.placement.hand_layouts import plate_table1, structure_exciters, structure_sensors
from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.placement.plan_file import read_plan
from massline.core.rigid_body import RigidBody
from massline.uff.writer import write_uff
from massline.identify.diagnose.effects import parse_effect
from massline.virtual.elastic import Material
from massline.virtual.measurement import Noise
from massline.virtual.suspension import Cord, Suspension, hung_over
from massline.virtual.acquisition import Acquisition, accelerometer_masses, run

EXACT = Acquisition(100.0, 200, Noise(0, 0), dc_line=False)
TRIAXIAL_POINTS = [[0.08, 0.12, 0.05], [0.16, 0.03, 0.1]]


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def with_triaxials() -> Lines:
    """The structure's six uniaxial sensors and two triaxial ones: 12 channels, 8 housings."""
    return structure_sensors() + Lines.triaxials(TRIAXIAL_POINTS)


def test_a_triaxial_is_one_housing():
    points = housing_points(with_triaxials())
    assert len(points) == 8
    np.testing.assert_array_equal(points[6:], TRIAXIAL_POINTS)
    assert Housings.on(with_triaxials(), 0.025).total == pytest.approx(0.2)
    assert Housings.on(with_triaxials(), 0.0).count == 0


def test_subtracting_the_housings_recovers_the_bare_body_exactly(structure):
    """Noiseless masslines of the structure with 8 housings of 25 g on (200 g, 5 %): the bare body to 1e-9."""
    rec, truth = run(structure, with_triaxials(), structure_exciters(), setup=replace(EXACT, sensor_mass=0.025))
    found = identify_recording(rec, (5, 95), draws=0, sensor_mass=0.025)
    assert found.housings.count == 8 and found.tested.mass == pytest.approx(truth["loaded"]["mass"], rel=1e-12)
    assert_body_close(found.body, structure, rtol=1e-9)
    plain = identify_recording(rec, (5, 95), draws=0)
    assert_body_close(plain.body, RigidBody(**{k: truth["loaded"][k] for k in ("mass", "cog", "inertia_cog")}))
    assert plain.payload["sensor_mass"] == 0.0 and "as_tested" not in plain.payload
    assert found.payload["as_tested"]["mass"] == pytest.approx(truth["loaded"]["mass"], rel=1e-12)


def test_plate_housings_are_taken_off_in_the_plates_parameters(plate):
    """Plate data (§2.3), housings 2.5 mm above the mid-plane: mass and in-plane CoG exact; J_G's in-plane entries
    within the plate model's own approximation, (Σ m_k z_k)²/m: the housings lift the CoG off the mid-plane, and
    the z-lines see J_xx and J_yy less m z_G² (the in-plane motions they couple to are not measured)."""
    sensors, exciters = plate_table1()
    rec, truth = run(plate, sensors, exciters, setup=replace(EXACT, sensor_mass=0.01))
    found = identify_recording(rec, (5, 95), draws=0, sensor_mass=0.01)
    assert found.planar and found.housings.count == 4
    assert found.body.mass == pytest.approx(plate.mass, rel=1e-9)
    np.testing.assert_allclose(found.body.cog[:2], plate.cog[:2], atol=1e-9 * plate.radius_of_gyration)
    lift = (0.01 * sensors.points[:, 2].sum()) ** 2 / truth["loaded"]["mass"]
    J, J0 = found.body.inertia_cog[:2, :2], plate.inertia_cog[:2, :2]
    np.testing.assert_allclose(J, J0, atol=1.01 * lift)
    assert lift < 1e-5 * np.abs(J0).max()


vectors = st.tuples(*[st.floats(-0.3, 0.3, allow_nan=False)] * 3).map(np.array)


@settings(max_examples=50, deadline=None)
@given(points=st.lists(vectors, min_size=1, max_size=8), mass=st.floats(1e-3, 0.1), rotvec=vectors, shift=vectors)
def test_taking_k_housings_off_is_exact_and_frame_invariant(structure, points, mass, rotvec, shift):
    """θ_tested = θ_bare + Σ θ_k, so taking the k housings off gives the bare body back, in any frame."""
    housings = Housings.alike(mass, np.array(points))
    tested = RigidBody.from_theta(structure.theta + housings.theta())
    assert_body_close(housings.removed_from(tested), structure, rtol=1e-11)
    R = Rotation.from_rotvec(3 * rotvec).as_matrix()
    moved = Housings.alike(mass, np.array(points) @ R.T + shift)
    there = moved.removed_from(tested.transformed(R, shift))
    assert_body_close(there, structure.transformed(R, shift), rtol=1e-11)


def test_a_point_mass_has_the_parameters_of_a_point():
    r = np.array([0.1, -0.2, 0.05])
    np.testing.assert_allclose(point_mass_theta(0.02, r), RigidBody(0.02, r, np.zeros((3, 3))).theta, atol=1e-16)


def test_the_bare_body_keeps_the_covariance_of_theta(structure):
    """The housings' mass is exact: θ's covariance (SI) is the same, and so is the mass's 1-σ."""
    sensors = with_triaxials()
    tested = RigidBody.from_theta(structure.theta + Housings.on(sensors, 0.025).theta())
    data = synthesise(tested, sensors, structure_exciters(2))
    sigma = 0.01 * np.abs(data.values) + 1e-3 / tested.mass
    found = estimate(data, sigma)
    bare = Housings.on(sensors, 0.025).removed(found)
    si = [f.covariance * np.outer(f.model.scale, f.model.scale) for f in (found, bare)]
    np.testing.assert_allclose(si[1], si[0], rtol=1e-10, atol=1e-12 * np.abs(si[0]).max())
    assert_body_close(bare.body, structure, rtol=1e-9)


def test_housings_heavier_than_the_body_are_refused(structure):
    data = synthesise(structure, with_triaxials(), structure_exciters(2))
    found = estimate(data, 0.01 * np.abs(data.values) + 1e-3 / structure.mass)
    with pytest.raises(MasslineError, match="--sensor-mass: 8 accelerometer housings × 1 kg leave no physical body"):
        Housings.on(with_triaxials(), 1.0).removed(found)


@pytest.fixture(scope="module")
def structure_plan():
    """The planner's layout on the structure: 12 uniaxial and 2 triaxial accelerometers (14 housings), 4 hits."""
    return session_cache.plan("structure", "--sensors", "12", "--triaxial", "2", "--exciters", "4")


@pytest.fixture(scope="module")
def loaded_test(structure_plan):
    """The realistic structure test but the housings' mass: FE modes (2 cm quadratic tetrahedra), a cord 2 cm
    above the CoG, the record up to f1/2.5, 1 % noise and 2 % transverse sensitivity on every channel."""
    mesh = bundled("structure")
    body = mesh.nominal
    sensors, exciters, _ = read_plan(structure_plan)
    modes = session_cache.fe_modes(mesh.mesh, Material(210e9, 0.3, mesh.density), 12, 0.02)
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    transverse = (parse_effect("transverse_sensitivity=0.02@all"),)
    return body, sensors, exciters, modes, cord, transverse, modes.frequencies_hz[0] / 2.5


def errors(found: RigidBody, body: RigidBody) -> tuple[float, float, float, float]:
    """Mass (fraction), CoG (m, worst axis), principal moments (fraction, worst) and J_G (Frobenius, fraction)."""
    return (
        abs(found.mass / body.mass - 1),
        np.abs(found.cog - body.cog).max(),
        np.abs(found.principal_moments / body.principal_moments - 1).max(),
        np.linalg.norm(found.inertia_cog - body.inertia_cog) / np.linalg.norm(body.inertia_cog),
    )


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("grams", [10, 25])
def test_a_loaded_virtual_test_gives_the_bare_body(loaded_test, grams, seed):
    """14 housings of 10 g (3.5 % of the 4 kg body) or 25 g (8.8 %): --sensor-mass recovers the bare body within
    mass 0.3 %, CoG 1 mm, principal moments 1 %, J_G 1.5 % (Frobenius); without it, the body is the loaded one."""
    body, sensors, exciters, modes, cord, effects, fmax = loaded_test
    masses, points = accelerometer_masses(sensors, grams / 1e3)
    loaded_cog = (body.mass * body.cog + masses @ points) / (body.mass + masses.sum())
    rehung = hung_over(cord, loaded_cog)  # the lab re-hangs the body level with its accelerometers on
    rec, truth = run(
        body, sensors, exciters, modes, rehung, effects, Acquisition(fmax, 2000, sensor_mass=grams / 1e3), seed
    )
    found = identify_recording(rec, None, draws=20, sensor_mass=grams / 1e3)
    assert found.housings.count == len(truth["added_masses"]["mass"]) == 14
    mass, cog, moments, tensor = errors(found.body, body)
    print(f"{grams} g, seed {seed}: mass {mass:.3%} CoG {cog * 1e3:.3f} mm moments {moments:.3%} J_G {tensor:.3%}")
    assert mass < 0.003 and cog < 1e-3 and moments < 0.01 and tensor < 0.015
    assert abs(found.body.mass - body.mass) < 3 * found.std["mass"]
    plain = identify_recording(rec, None, draws=0)
    added = 14 * grams / 1e3 / body.mass
    assert plain.body.mass / body.mass - 1 == pytest.approx(added, rel=0.1)
    loaded = errors(plain.body, body)
    print(f"   without --sensor-mass: mass {loaded[0]:.3%} CoG {loaded[1] * 1e3:.3f} mm moments {loaded[2]:.3%}")
    assert loaded[2] > 0.09  # the loaded body's moments: 9.6 % (10 g) and 24.1 % (25 g) off


@pytest.mark.parametrize(
    "text,mass,sd",
    [
        ("4.012", 4.012, 4.012 * 5e-4),
        ("4.012±0.002", 4.012, 0.002),
        ("4.012 +- 2e-3", 4.012, 0.002),
        ("4.012+/-0.002", 4.012, 0.002),
        ("4.012±0.1%", 4.012, 0.004012),
    ],
)
def test_a_scale_reading_is_read_as_written(text, mass, sd):
    reading = WeighedMass.parse(text)
    assert reading.mass == pytest.approx(mass) and reading.sd == pytest.approx(sd)


@pytest.mark.parametrize("text", ["-4", "0", "nan", "inf", "4 kg", "4±0", "4±-0.1", "4±nan", "4±", "±0.1", ""])
def test_a_bad_scale_reading_is_refused(text):
    with pytest.raises(MasslineError, match="--weighed-mass .* KG > 0 kg"):
        WeighedMass.parse(text)


def minimal_test(body, seed):
    """The paper's 18 masslines (6 sensors × 3 hits) on the structure: a cord, 1 % noise, 2 % transverse
    sensitivity on every channel; and a 0.05 % scale's reading of it (its error drawn with the same seed)."""
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    effects = (parse_effect("transverse_sensitivity=0.02@all"),)
    rec, _ = run(body, structure_sensors(), structure_exciters(), None, cord, effects, Acquisition(200.0, 2000), seed)
    sd = 5e-4 * body.mass
    return rec, WeighedMass(body.mass + sd * np.random.default_rng(100 + seed).standard_normal(), sd)


def figures(found, body) -> np.ndarray:
    """Errors then 1-σ: mass (fraction), CoG x, y, z (m), principal moments (fraction)."""
    moments = body.principal_moments
    std = found.std
    return np.concatenate(
        [
            [found.body.mass / body.mass - 1],
            found.body.cog - body.cog,
            found.body.principal_moments / moments - 1,
            [std["mass"] / body.mass],
            std["cog"],
            std["principal_moments"] / moments,
        ]
    )


@pytest.mark.slow
def test_a_weighed_mass_sharpens_the_cog_and_the_inertia(structure):
    """Bretl & Conti's case on the minimal layout: with a 0.05 % scale, the 1-σ of the mass, of every CoG
    component and of every principal moment drop, and so do their RMS errors over 10 seeds. A calibrated chain
    (the scale's information against the masslines' noise: the estimate does not yet take the force's scale as a
    parameter the scale could calibrate)."""
    rows = {"masslines": [], "weighed": []}
    calibrated = Calibration(0.0, 0.0)
    for seed in range(10):
        rec, reading = minimal_test(structure, seed)
        rows["masslines"].append(figures(identify_recording(rec, None, draws=0, calibration=calibrated), structure))
        found = identify_recording(rec, None, draws=0, weighed=reading, calibration=calibrated)
        rows["weighed"].append(figures(found, structure))
    rms = {k: np.sqrt(np.mean(np.square(v)[:, :7], axis=0)) for k, v in rows.items()}
    sigma = {k: np.median(np.array(v)[:, 7:], axis=0) for k, v in rows.items()}
    for k in rows:
        print(f"{k}: RMS error", np.round(rms[k] * [100, 1e3, 1e3, 1e3, 100, 100, 100], 3), "(%, mm, %)")
        print(f"{k}: median σ ", np.round(sigma[k] * [100, 1e3, 1e3, 1e3, 100, 100, 100], 3), "(%, mm, %)")
    assert np.all(sigma["weighed"] < sigma["masslines"])
    assert sigma["weighed"][0] == pytest.approx(5e-4, rel=0.02)
    assert rms["weighed"][0] < 0.25 * rms["masslines"][0]
    assert np.linalg.norm(rms["weighed"][1:4]) < 0.75 * np.linalg.norm(rms["masslines"][1:4])
    assert np.all(rms["weighed"][4:] < rms["masslines"][4:])


def test_every_bootstrap_draw_keeps_the_scale(structure):
    """A tight scale (1e-5) holds every draw's mass within it; the masslines alone spread it 10 times wider."""
    sensors = with_triaxials()
    data = synthesise(structure, sensors, structure_exciters(2))
    sigma = 0.01 * np.abs(data.values) + 1e-3 / structure.mass
    noisy = type(data)(
        data.values + sigma * np.random.default_rng(3).standard_normal(sigma.shape), sensors, data.exciters
    )
    spread = {}
    for name, weighed in (("masslines", None), ("scale", WeighedMass(structure.mass, 1e-5 * structure.mass))):
        found = estimate(noisy, sigma, weighed=weighed)
        spread[name] = np.std([b.mass for b in bootstrap(noisy, sigma, found, 20)]) / structure.mass
    print(spread)
    assert spread["scale"] < 1e-5 < 0.1 * spread["masslines"]


def test_a_scale_that_disagrees_with_the_masslines_is_warned(structure):
    """A reading 1 % heavy (20σ of the scale) against masslines good to ~0.1 %: a warning says so."""
    rec, _ = run(structure, with_triaxials(), structure_exciters(2), setup=Acquisition(100.0, 200, Noise(0.01, 0)))
    found = identify_recording(rec, (5, 95), draws=0, weighed=WeighedMass(1.01 * structure.mass, 5e-4 * structure.mass))
    warned = codes_of(found.warnings)  # the reading is a measured row: it raises χ² too
    assert "weighed_mass_disagrees" in warned and warned <= {"weighed_mass_disagrees", "model_misfit"}, warned
    agree = identify_recording(rec, (5, 95), draws=0, weighed=WeighedMass(structure.mass, 5e-4 * structure.mass))
    assert not agree.warnings and abs(agree.best.weighed_z) < 3


@pytest.fixture(scope="module")
def loaded_uff(structure, tmp_path_factory):
    """Noiseless masslines of the structure with 8 housings of 25 g on (6 uniaxial, 2 triaxial), as a UFF."""
    rec, truth = run(structure, with_triaxials(), structure_exciters(), setup=replace(EXACT, sensor_mass=0.025))
    path = tmp_path_factory.mktemp("loaded") / "loaded.uff"
    write_uff(path, rec)
    return path, truth


def test_identify_json_has_the_bare_body_and_the_body_as_tested(structure, loaded_uff, tmp_path):
    path, truth = loaded_uff
    out = tmp_path / "id.json"
    run_ = massline("identify", path, "--band", 5, 95, "--bootstrap", 0, "--sensor-mass", 0.025, "--json", out)
    assert run_.returncode == 0, run_.stderr
    assert "8 accelerometer housings × 25 g = 200 g subtracted" in run_.stdout and "bare body" in run_.stdout
    found = json.loads(out.read_text())
    assert found["sensor_mass"] == 0.025
    assert found["mass"] == pytest.approx(structure.mass, rel=1e-9)
    tested = found["as_tested"]
    assert tested["mass"] == pytest.approx(truth["loaded"]["mass"], rel=1e-9)
    np.testing.assert_allclose(tested["cog"], truth["loaded"]["cog"], atol=1e-9 * structure.radius_of_gyration)
    assert set(tested) == {
        "mass",
        "cog",
        "inertia_cog",
        "principal_moments",
        "principal_axes",
        "std",
        "band_hz",
        "planar",
    }
    assert tested["std"]["mass"] == pytest.approx(found["std"]["mass"], rel=1e-9)
    weighed = tmp_path / "w.json"
    args = ("--sensor-mass", 0.025, "--weighed-mass", f"{structure.mass:.6f}±0.002", "--calibration", 0)
    args += ("--json", weighed)
    run_ = massline("identify", path, "--band", 5, 95, "--bootstrap", 0, *args)
    assert run_.returncode == 0, run_.stderr
    assert "weighed mass" in run_.stdout and "used as a prior" in run_.stdout
    assert json.loads(weighed.read_text())["std"]["mass"] < 0.002


def test_without_a_sensor_mass_the_json_is_unchanged(loaded_uff, tmp_path):
    out = tmp_path / "id.json"
    assert massline("identify", loaded_uff[0], "--band", 5, 95, "--bootstrap", 0, "--json", out).returncode == 0
    found = json.loads(out.read_text())
    assert found["sensor_mass"] == 0.0 and "as_tested" not in found
    assert found["mass"] == pytest.approx(loaded_uff[1]["loaded"]["mass"], rel=1e-9)


@pytest.mark.parametrize(
    "option,value,words",
    [
        ("--sensor-mass", "-0.01", "--sensor-mass '-0.01': .* 0 ≤ KG ≤ 10"),
        ("--sensor-mass", "nan", "--sensor-mass 'nan'"),
        ("--sensor-mass", "inf", "--sensor-mass 'inf'"),
        ("--sensor-mass", "ten", "--sensor-mass 'ten'"),
        ("--sensor-mass", "5", "--sensor-mass: 8 accelerometer housings × 5 kg leave no physical body"),
        ("--weighed-mass", "-4", "--weighed-mass '-4': .* KG > 0 kg"),
        ("--weighed-mass", "0", "--weighed-mass '0'"),
        ("--weighed-mass", "nan", "--weighed-mass 'nan'"),
        ("--weighed-mass", "inf", "--weighed-mass 'inf'"),
        ("--weighed-mass", "4±0", "--weighed-mass '4±0'"),
        ("--weighed-mass", "4 kg", "--weighed-mass '4 kg'"),
    ],
)
def test_bad_masses_are_refused_in_one_line(loaded_uff, option, value, words):
    result = cli("identify", loaded_uff[0], "--band", 5, 95, "--bootstrap", 0, f"{option}={value}")
    assert result.returncode == 2, result.stderr
    assert re.search(words, result.stderr) and "Traceback" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_a_paper_method_takes_no_scale(loaded_uff):
    result = massline("identify", loaded_uff[0], "--band", 5, 95, "--method", "method2+method3", "--weighed-mass", "4")
    assert result.returncode == 2 and "--weighed-mass needs --method best" in result.stderr


def test_the_report_says_what_was_taken_off_and_weighed(structure):
    from massline.reports.identification_report import masses_note

    rec, _ = run(structure, with_triaxials(), structure_exciters(), setup=replace(EXACT, sensor_mass=0.025))
    reading = WeighedMass(4.0, 0.002)
    note = masses_note(identify_recording(rec, (5, 95), draws=0, sensor_mass=0.025, weighed=reading))
    assert "8 accelerometer housings × 25 g (200 g in all) are subtracted" in note and "4 ± 0.002 kg" in note
    assert masses_note(identify_recording(rec, (5, 95), draws=0)) == ""
