"""The virtual test: instrumentation effects, the impact route, and identification from its FRFs."""

import numpy as np
import pytest
from conftest import bundled

from massline.core.band import Band
from massline.core.errors import MasslineError
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.core.lines import Lines
from massline.core.masslines import Masslines, synthesise
from massline.core.methods import identify
from massline.virtual.analyser import LINE_COUNTS, impact_setup
from massline.identify.diagnose.effects import parse_effect
from massline.virtual.measurement import ImpactTest, Noise, half_sine_spectrum
from massline.virtual.suspension import single_cord
from massline.virtual.acquisition import Acquisition, run

QUIET = Acquisition(fmax=200.0, lines=400, noise=Noise(0.0, 0.0), dc_line=False)


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def ideal(body, sensors=None, exciters=None):
    return synthesise(body, sensors or structure_sensors(), exciters or structure_exciters()).values


def record(body, *effects, setup=QUIET, suspension=None, sensors=None, seed=0):
    sensors = sensors or structure_sensors()
    return run(body, sensors, structure_exciters(), None, suspension, tuple(map(parse_effect, effects)), setup, seed)


def test_free_rigid_noiseless_recording_is_the_massline(structure):
    rec, truth = record(structure)
    np.testing.assert_allclose(rec.frf, np.repeat(ideal(structure)[:, :, None], 400, axis=2), rtol=1e-12)
    assert truth["effects"] == []


def test_polarity_gain_and_swap_act_on_their_channels(structure):
    H0 = ideal(structure)
    rec, _ = record(structure, "sensor_polarity@2", "sensor_gain=0.05@4", "channel_swap@5,6")
    H = rec.frf[:, :, 0].real
    np.testing.assert_allclose(H[1], -H0[1], rtol=1e-12)
    np.testing.assert_allclose(H[3], 1.05 * H0[3], rtol=1e-12)
    np.testing.assert_allclose(H[[4, 5]], H0[[5, 4]], rtol=1e-12)
    np.testing.assert_allclose(H[[0, 2]], H0[[0, 2]], rtol=1e-12)


@pytest.mark.parametrize("degrees", [2.0, 10.0])
def test_sensor_direction_tilts_by_the_angle(structure, degrees):
    _, truth = record(structure, f"sensor_direction={degrees}@3")
    read = np.array(truth["instrumented"]["sensor_vectors"][2])
    planned = structure_sensors().directions[2]
    assert np.degrees(np.arccos(read @ planned / np.linalg.norm(read))) == pytest.approx(degrees, rel=1e-9)


def test_triaxial_turns_as_one_block(structure):
    triax = Lines.triaxials(np.array([[0.05, 0.02, 0.03], [-0.04, 0.05, 0.0], [0.0, -0.05, 0.04]]))
    _, truth = record(structure, "sensor_direction=5@2", sensors=triax)
    read = np.array(truth["instrumented"]["sensor_vectors"])
    R = read[:3].T  # columns: the turned x, y, z axes of accelerometer 1
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.degrees(np.arccos((np.trace(R) - 1) / 2)) == pytest.approx(5.0)
    np.testing.assert_allclose(read[3:], triax.directions[3:])


def test_transverse_sensitivity_reads_across(structure):
    _, truth = record(structure, "transverse_sensitivity=0.03@all")
    read = np.array(truth["instrumented"]["sensor_vectors"])
    planned = structure_sensors().directions
    np.testing.assert_allclose(np.einsum("ij,ij->i", read, planned), 1.0)
    np.testing.assert_allclose(np.linalg.norm(read - planned, axis=1), 0.03)


def test_locations_move_perpendicular_to_the_line(structure):
    _, truth = record(structure, "sensor_location=0.004@1", "excitation_location=0.006@2")
    moved = np.array(truth["instrumented"]["sensor_points"][0]) - structure_sensors().points[0]
    hit = np.array(truth["instrumented"]["exciter_points"][1]) - structure_exciters().points[1]
    assert np.linalg.norm(moved) == pytest.approx(0.004) and abs(moved @ structure_sensors().directions[0]) < 1e-15
    assert np.linalg.norm(hit) == pytest.approx(0.006) and abs(hit @ structure_exciters().directions[1]) < 1e-15


def test_sensor_masses_load_the_body(structure):
    rec, truth = record(structure, "sensor_mass_loading=0.02@all")
    assert truth["loaded"]["mass"] == pytest.approx(structure.mass + 0.02 * 6)
    found = identify(Masslines(rec.frf[:, :, 0].real, structure_sensors(), structure_exciters()))
    assert found.mass == pytest.approx(truth["loaded"]["mass"], rel=1e-10)


@pytest.mark.parametrize(
    "text,message",
    [("wobble=1", "unknown effect"), ("sensor_gain", "needs a size"), ("channel_swap@3", "two channels")],
)
def test_bad_effects_are_named(text, message):
    with pytest.raises(MasslineError, match=message):
        parse_effect(text)


def test_effect_on_a_missing_sensor(structure):
    with pytest.raises(MasslineError, match="no sensor 9"):
        record(structure, "sensor_gain=0.1@9")


def band_average(rec, band, top=None):
    low, high = band
    keep = (rec.frequencies >= low) & (rec.frequencies <= min(high, top or np.inf))
    return Masslines(rec.frf[:, :, keep].real.mean(axis=2), rec.sensors, rec.exciters)


@pytest.mark.parametrize("pulse", [0.2e-3, 2e-3])
def test_finite_pulse_keeps_the_massline(structure, pulse):
    suspension = single_cord(structure, structure.mass * 9.81 / 0.25, 1.0, 0.05)
    impact = ImpactTest(pulse=pulse, force_noise=0.0, response_noise=0.0, averages=1)
    rec, truth = record(structure, suspension=suspension, setup=Acquisition(fmax=200.0, lines=800, impact=impact))
    found = band_average(rec, truth["band_hz"], top=150.0).values
    H0 = ideal(structure)
    assert np.linalg.norm(found - H0) / np.linalg.norm(H0) < 2e-3


def test_noisy_impact_test_identifies_the_mass(structure):
    suspension = single_cord(structure, structure.mass * 9.81 / 0.25, 1.0, 0.05)
    rec, truth = record(structure, suspension=suspension, setup=Acquisition(fmax=200.0, lines=800, impact=ImpactTest()))
    assert rec.coherence[:, :, rec.frequencies >= truth["band_hz"][0]].min() > 0.9  # low at DC, low lines
    found = identify(band_average(rec, truth["band_hz"], top=150.0))
    assert found.mass == pytest.approx(structure.mass, rel=0.005)


# ---- the analyser a test engineer sets up for an impact test

BRACKET_BAND = Band(34.5, 164.3)
PENDULUM = np.array([0.0, 0.487, 0.487, 0.997, 2.66, 4.22])  # the bracket on its cord, Hz (0: yaw, free)


def test_impact_setup_holds_the_lowest_support_mode():
    setup = impact_setup(BRACKET_BAND, PENDULUM, 0.01)
    assert setup.warnings == () and setup.lines in LINE_COUNTS and 3 <= setup.fmax / BRACKET_BAND.high < 4
    assert np.log(100) / setup.record <= 0.05 * 2 * np.pi * 0.487  # the window adds ≤ 5 % damping to it
    assert setup.lines == LINE_COUNTS[0] or np.log(100) / (setup.record / 2) > 0.05 * 2 * np.pi * 0.487
    pulse = half_sine_spectrum(np.array([0.0, BRACKET_BAND.high, setup.fmax]), 0.0, setup.pulse, 1.0)
    assert 20 * np.log10(np.abs(pulse[1:]) / np.abs(pulse[0])) == pytest.approx([-0.95, -10.0], abs=0.1)


def test_settings_given_by_hand_are_kept_and_what_they_truncate_is_said():
    short = impact_setup(BRACKET_BAND, PENDULUM, 0.01, fmax=500.0, lines=1600, pulse=8e-3)
    assert (short.fmax, short.lines, short.pulse) == (500.0, 1600, 8e-3)
    record, pulse = short.warnings
    assert "3.2 s" in record and "choose --lines 25600" in record
    assert "8 ms pulse" in pulse and "choose --impact 2 " in pulse
    wide = impact_setup(BRACKET_BAND, PENDULUM, 0.01, fmax=3000.0)
    assert wide.lines == LINE_COUNTS[-1] and "choose --fmax 1600 --lines 51200" in wide.warnings[0]


def test_both_routes_record_the_dc_line_as_exporters_do(structure):
    """A real 0 Hz value with a low coherence, before lines at Δf … fmax; the direct route's coherence is
    |H|²/(|H|² + σ²) for its relative noise σ/|H| = 1 %."""
    suspension = single_cord(structure, structure.mass * 9.81 / 0.25, 1.0, 0.05)
    direct, _ = record(structure, setup=Acquisition(fmax=200.0, lines=400))
    impact, _ = record(structure, suspension=suspension, setup=Acquisition(200.0, 800, impact=ImpactTest()))
    for rec, lines in ((direct, 400), (impact, 800)):
        assert len(rec.frequencies) == lines + 1 and rec.frequencies[0] == 0 and rec.frequencies[1] > 0
        assert np.all(rec.frf[:, :, 0].imag == 0) and np.median(rec.coherence[:, :, 0]) < 0.5
    assert np.all(np.abs(direct.frf[:, :, 0]) >= np.median(np.abs(direct.frf[:, :, 1:]), axis=2))
    np.testing.assert_allclose(direct.coherence[:, :, 1:], 1 / (1 + 0.01**2), rtol=1e-12)
