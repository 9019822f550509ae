"""identify's uncertainty budget: each source's 1-σ is its propagation, the sources combine in quadrature to the
reported 1-σ, the force calibration moves the mass one for one and the CoG not at all."""

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from massline.core.calibration import Calibration
from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.masslines import Masslines, synthesise
from massline.core.properties import property_vector
from massline.core.rigid_body import RigidBody, mass_matrix
from massline.identify.estimator import estimate
from massline.core.lines import perpendicular_bases
from massline.identify.sensor_mass import Housings
from massline.identify.uncertainty import identified_spread
from massline.core.uncertainty_budget import SOURCES
from massline.cli.app import run
from massline.core.model import RigidModel
from massline.placement.predicted_budget import massline_sigma, massline_variance_factor, predicted_budget
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.virtual.chain_errors import draw_chain_errors
from massline.identify.pipeline import identify_recording
from massline.placement.plan_file import read_plan
from massline.virtual.acquisition import Acquisition
from massline.virtual.planned_test import plan_mesh
from massline.virtual.simulation import simulate_test

ROTATION = Rotation.from_euler("xyz", [25, -40, 60], degrees=True).as_matrix()
BODY = RigidBody(3.2, np.array([0.01, -0.02, 0.03]), ROTATION @ np.diag([0.02, 0.03, 0.045]) @ ROTATION.T)
QUIET = 1e-9  # the masslines' relative 1-σ: noise ~0


def layout(n_s: int = 12, n_e: int = 4, seed: int = 1) -> tuple[Lines, Lines]:
    """Oblique sensor and exciter lines over a 0.4 m body."""
    rng = np.random.default_rng(seed)
    sensors = Lines(rng.uniform(-0.2, 0.2, (n_s, 3)), rng.normal(size=(n_s, 3)))
    return sensors, Lines(rng.uniform(-0.2, 0.2, (n_e, 3)), rng.normal(size=(n_e, 3)))


def quiet_spread(data: Masslines, calibration: Calibration, transverse: float = 0.0, quiet: float = QUIET):
    """The spread of exact masslines with noise ~0 (``quiet``, relative) and the given type-B sources alone."""
    sigma = quiet * np.abs(data.values) + 1e-12
    found = estimate(data, sigma, transverse=transverse)
    calibration = Calibration(calibration.sensor, calibration.force, transverse)
    spread = identified_spread(data, sigma, np.zeros_like(sigma), found, bare=found, housings=Housings(), draws=0,
                               calibration=calibration)  # fmt: skip
    return found, spread


def moved(data: Masslines, factors: np.ndarray, transverse: float = 0.0) -> np.ndarray:
    """The property vector re-estimated on masslines scaled row by row by ``factors`` (n_s,) (noise ~0)."""
    values = data.values * factors[:, None]
    sigma = QUIET * np.abs(values) + 1e-12
    found = estimate(Masslines(values, data.sensors, data.exciters), sigma, transverse=transverse)
    return property_vector(found.body, False)


def test_the_force_calibration_alone_gives_its_propagated_sigma_and_moves_the_mass_one_for_one():
    data = synthesise(BODY, *layout())
    found, spread = quiet_spread(data, Calibration(0.0, 0.01))
    budget = spread.budget
    exact = moved(data, np.full(12, 1.01)) - property_vector(found.body, False)
    assert budget.parts["force_calibration"][0] / BODY.mass == pytest.approx(0.01, rel=1e-6)
    assert budget.parts["force_calibration"][0] == pytest.approx(abs(exact[0]), rel=0.02)  # 1/(1.01) to first order
    np.testing.assert_allclose(budget.parts["force_calibration"][1:4], 0.0, atol=1e-9 * BODY.radius_of_gyration)
    moments = BODY.principal_moments
    np.testing.assert_allclose(budget.parts["force_calibration"][13:16] / moments, 0.01, rtol=1e-5)
    for source in ("sensor_calibration", "transverse", "weighed_mass", "truncation"):
        assert np.all(budget.parts[source] == 0), source
    assert budget.parts["noise"][0] < 1e-6 * budget.parts["force_calibration"][0]
    assert spread.bare["mass"] == pytest.approx(0.01 * BODY.mass, rel=1e-6)


def test_the_sensor_calibration_alone_is_the_channels_moves_in_quadrature():
    data = synthesise(BODY, *layout())
    found, spread = quiet_spread(data, Calibration(0.01, 0.0))
    reference = property_vector(found.body, False)
    step = 1e-4  # small enough for the first order, large enough for the estimator's digits
    moves = np.array([(moved(data, 1 + step * np.eye(12)[i]) - reference) / step * 0.01 for i in range(12)])
    expected = np.sqrt(np.sum(moves**2, axis=0))
    got = spread.budget.parts["sensor_calibration"]
    for k in [0, 1, 2, 3, 13, 14, 15]:  # mass, CoG, principal moments
        assert got[k] == pytest.approx(expected[k], rel=2e-3), k
    assert spread.budget.parts["force_calibration"][0] == 0


def tilted_masslines(body: RigidBody, sensors: Lines, exciters: Lines, readings: np.ndarray) -> np.ndarray:
    """H = S M_O⁻¹ Wᵀ with each sensor reading along its axis plus ``readings`` (n_s, 3) across it (DESIGN.md)."""
    vectors = sensors.directions + readings
    S = np.hstack([vectors, np.cross(sensors.points, vectors)])
    W = np.hstack([exciters.directions, np.cross(exciters.points, exciters.directions)])
    return S @ np.linalg.solve(mass_matrix(body.theta), W.T)


def test_the_transverse_prior_alone_is_the_moves_of_each_transverse_reading_in_quadrature():
    sensors, exciters = layout(n_s=6, n_e=3)  # a minimal layout: the data cannot see the transverse readings
    data = synthesise(BODY, sensors, exciters)
    found, spread = quiet_spread(data, Calibration(0.0, 0.0), transverse=0.03, quiet=1e-6)  # 1e-9: S singular
    reference = property_vector(found.body, False)
    axes = perpendicular_bases(sensors.directions)
    moves, step = [], 1e-4  # the first order: a tilt of the prior's 3 % makes the constraint bite on this body
    for i in range(6):
        for k in range(2):
            readings = np.zeros((6, 3))
            readings[i] = step * axes[i, :, k]
            values = tilted_masslines(BODY, sensors, exciters, readings)
            sigma = 1e-6 * np.abs(values)
            again = estimate(Masslines(values, sensors, exciters), sigma, transverse=0.03)
            moves.append((property_vector(again.body, False) - reference) * 0.03 / step)  # at the prior's 1-σ
    expected = np.sqrt(np.sum(np.array(moves) ** 2, axis=0))
    parts = spread.budget.parts
    for k in [0, 1, 2, 3, 13, 14, 15]:
        assert parts["transverse"][k] == pytest.approx(expected[k], rel=0.05), k
    assert parts["noise"][0] < 1e-3 * parts["transverse"][0]


def test_the_sources_combine_in_quadrature_to_the_reported_sigma():
    sensors, exciters = layout()
    data = synthesise(BODY, sensors, exciters)
    rng = np.random.default_rng(3)
    noisy = Masslines(data.values * (1 + 0.002 * rng.normal(size=data.values.shape)), sensors, exciters)
    sigma = 0.002 * np.abs(data.values)
    found = estimate(noisy, sigma)
    spread = identified_spread(noisy, sigma, 0.01 * sigma, found, bare=found, housings=Housings(), draws=20)
    budget = spread.budget
    squares = sum(budget.parts[s] ** 2 for s in SOURCES)
    np.testing.assert_allclose(budget.total**2, squares, rtol=1e-12)
    assert spread.bare["mass"] == pytest.approx(np.sqrt(squares[0]), rel=1e-12)
    np.testing.assert_allclose(spread.bare["principal_moments"], np.sqrt(squares[13:16]), rtol=1e-12)
    for row in budget.payload()["properties"].values():
        assert sum(v["share"] for v in row["sources"].values()) == pytest.approx(1.0, rel=1e-9)


def test_identify_reports_the_budget_and_a_calibrated_chain_removes_its_sources(bracket_recording, tmp_path, capsys):
    out = tmp_path / "i.json"
    assert run(["identify", str(bracket_recording), "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "uncertainty budget" in printed and "force transducer's 1 % calibration limits the mass" in printed
    found = json.loads(out.read_text())
    mass = found["uncertainty_budget"]["properties"]["mass"]
    assert mass["std"] == pytest.approx(found["std"]["mass"], rel=1e-9)
    assert mass["sources"]["force_calibration"]["std"] / found["mass"] == pytest.approx(0.01, rel=1e-3)
    assert found["std"]["mass"] / found["mass"] >= 0.01  # the calibration floor
    calibrated = tmp_path / "c.json"
    assert run(["identify", str(bracket_recording), "--calibration", "0", "--json", str(calibrated)]) == 0
    bare = json.loads(calibrated.read_text())["uncertainty_budget"]["properties"]["mass"]
    assert bare["sources"]["force_calibration"]["std"] == 0 and bare["sources"]["sensor_calibration"]["std"] == 0
    assert bare["std"] < 0.2 * mass["std"]


@pytest.fixture(scope="module")
def bracket_recording(bracket_default_plan, tmp_path_factory):
    """An ideal virtual test of the bracket's default plan (rigid: no FE solve; no chain errors, so that a
    calibrated chain's budget is the noise's)."""
    path = tmp_path_factory.mktemp("budget") / "b.uff"
    assert run(["simulate", str(bracket_default_plan), "--rigid", "--ideal", "--seed", "2", "--out", str(path)]) == 0
    return path


def test_the_plan_predicts_the_budget_identify_states_on_the_same_masslines():
    """The plan's budget (placement) and identify's on exact masslines with the σ the plan assumes: the same
    gains, so every source agrees to rounding."""
    sensors, exciters = layout()
    data = synthesise(BODY, sensors, exciters)
    frequencies = np.linspace(20.0, 200.0, 120)
    sigma = massline_sigma(data.values, 0.01, frequencies)
    found = estimate(data, sigma, transverse=0.03)
    spread = identified_spread(data, sigma, np.zeros_like(sigma), found, bare=found, housings=Housings(), draws=0,
                               calibration=Calibration())  # fmt: skip
    predicted = predicted_budget(RigidModel(BODY), sensors, exciters, line_noise=0.01, frequencies=frequencies,
                                 calibration=Calibration())  # fmt: skip
    for source in ("noise", "transverse", "sensor_calibration", "force_calibration"):
        got, expected = predicted.parts[source][:16], spread.budget.parts[source][:16]
        np.testing.assert_allclose(got, expected, rtol=1e-4, atol=1e-12 * np.abs(expected).max(), err_msg=source)


def test_a_massline_is_known_to_its_band_fits_variance():
    """σ_A = ν/√2 |H| √[(XᵀX)⁻¹]₀₀: more lines, less; a band too short to fit four terms, none."""
    few, many = np.linspace(20, 200, 50), np.linspace(20, 200, 200)
    assert 0.2 < massline_variance_factor(many) / massline_variance_factor(few) < 0.3  # ≈ 50/200
    assert massline_variance_factor(np.linspace(20, 400, 200)) < massline_variance_factor(many)  # a wider band
    assert massline_variance_factor(many[:4]) == np.inf
    assert massline_sigma(np.array([[2.0]]), 0.01, many)[0, 0] == pytest.approx(
        0.01 / np.sqrt(2) * 2.0 * np.sqrt(massline_variance_factor(many))
    )


def test_the_chain_errors_are_drawn_from_their_sigma_on_their_own_stream():
    directions = np.random.default_rng(0).normal(size=(4000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    errors = draw_chain_errors(Calibration(0.01, 0.02, 0.03), directions, seed=5)
    assert np.std(errors.gains - 1) == pytest.approx(0.01, rel=0.05)
    assert np.abs(np.einsum("nk,nk->n", errors.transverse, directions)).max() < 1e-12  # ⊥ each axis
    assert np.sqrt(np.mean(np.sum(errors.transverse**2, axis=1)) / 2) == pytest.approx(0.03, rel=0.05)
    again = draw_chain_errors(Calibration(0.01, 0.02, 0.03), directions, seed=5)
    assert again.force_gain == errors.force_gain and np.array_equal(again.gains, errors.gains)
    vectors = errors.reading_vectors(directions)
    np.testing.assert_allclose(np.einsum("nk,nk->n", vectors, directions), errors.gains, rtol=1e-12)


def test_the_virtual_test_draws_the_chain_by_default_and_ideal_draws_none(bracket_default_plan, tmp_path):
    real, ideal = tmp_path / "real.uff", tmp_path / "ideal.uff"
    base = ["simulate", str(bracket_default_plan), "--rigid", "--seed", "4", "--no-dc"]
    assert run([*base, "--out", str(real)]) == 0 and run([*base, "--ideal", "--out", str(ideal)]) == 0
    chain = json.loads(real.with_suffix(".truth.json").read_text())["chain"]
    assert json.loads(ideal.with_suffix(".truth.json").read_text())["chain"] is None
    assert {k: chain["calibration"][k] for k in ("sensor", "force", "transverse")} == {
        "sensor": 0.01, "force": 0.01, "transverse": 0.03
    }
    drawn = to_recording(read_uff(real)).frf
    clean = to_recording(read_uff(ideal)).frf
    # the force gauge's error divides every FRF; channel i reads (1 + ε_i) along its axis (+ across it)
    ratio = np.median(np.abs(drawn / clean), axis=(1, 2))
    expected = (1 + np.array(chain["sensor_gain_errors"])) / (1 + chain["force_gain_error"])
    np.testing.assert_allclose(ratio, expected, rtol=0.05)
    assert run([*base, "--ideal", "--calibration", "1", "--out", str(tmp_path / "x.uff")]) == 2


@pytest.mark.long  # 24 virtual tests of the bracket with its FE modes: about a minute
@pytest.mark.parametrize("minimal", [True, False], ids=["minimal", "default"])
def test_the_budget_is_the_error_and_the_plan_predicts_it(minimal):
    """On the bracket's plan, 12 default virtual tests (the chain's errors drawn): the RMS of error / reported 1-σ
    over mass, CoG and principal moments within 0.75–1.33, and the plan's predicted 1-σ within 25 % of identify's
    median reported 1-σ, property by property (benchmarks/uncertainty_budget.py runs all three bodies)."""
    import session_cache

    path = session_cache.plan("bracket", *(["--minimal"] if minimal else []))
    sensors, exciters, doc = read_plan(path)
    mesh = plan_mesh(doc, path)
    z, reported = [], []
    for seed in range(1, 13):
        test = simulate_test(doc, sensors, exciters, mesh, acquisition=Acquisition(chain=Calibration()), seed=seed)
        found = identify_recording(test.recording).payload
        truth = test.truth["nominal"]
        values, std = summary(found), summary(found["std"])
        true = summary({**truth, "principal_moments": np.linalg.eigvalsh(np.array(truth["inertia_cog"]))})
        z.append((values - true) / std)
        reported.append(std)
    rms = np.sqrt(np.mean(np.square(z)))
    ratio = summary(doc["predicted_std"]) / np.median(reported, axis=0)
    print(f"RMS z {rms:.2f}; predicted / reported {np.round(ratio, 2)}")
    assert 0.75 < rms < 1.33
    assert np.all(np.abs(ratio - 1) < 0.25), ratio


def summary(values: dict) -> np.ndarray:
    """mass, CoG (3), principal moments (3) of identify's value or std keys."""
    return np.concatenate([[values["mass"]], values["cog"], values["principal_moments"]]).astype(float)


def test_the_housings_tolerance_moves_the_bare_mass_by_each_housing_in_quadrature():
    sensors, exciters = layout()
    housings = Housings.alike(0.02, sensors.points[:4])
    tested = RigidModel(BODY).body(RigidModel(BODY).theta + housings.theta())
    data = synthesise(tested, sensors, exciters)
    sigma = QUIET * np.abs(data.values) + 1e-12
    found = estimate(data, sigma, transverse=0.0)
    calibration = Calibration(0.0, 0.0, 0.0).with_housings(0.05)
    spread = identified_spread(data, sigma, np.zeros_like(sigma), found, bare=housings.removed(found),
                               housings=housings, draws=0, calibration=calibration)  # fmt: skip
    assert spread.budget.parts["housings"][0] == pytest.approx(np.sqrt(4) * 0.05 * 0.02, rel=1e-6)
    assert np.all(spread.tested_budget.parts["housings"] == 0)  # the body as tested does not depend on them
    with pytest.raises(MasslineError):
        Calibration().with_housings(0.5)
