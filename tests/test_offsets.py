"""A moved accelerometer's offset read on identify's masslines (identify/diagnose/offsets.py)."""

import numpy as np
import pytest
from conftest import bundled

from massline.core.lines import Lines
from massline.identify.diagnose.effects import parse_effect
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.diagnose.offsets import offset_basis, read_offset
from massline.identify.pipeline import identify_recording
from massline.placement.hand_layouts import structure_exciters
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise


@pytest.fixture(scope="module")
def structure():
    return bundled("structure").nominal


def moved(structure, noise: float, seed: int = 3):
    """A free structure, 14 random channels, the third glued 8 mm off its point: the recording and the offset."""
    rng = np.random.default_rng(2)
    sensors = Lines(rng.normal(size=(14, 3)) * 0.1, rng.normal(size=(14, 3)))
    setup = Acquisition(100.0, 100, Noise(noise, 0))
    rec, truth = run(structure, sensors, structure_exciters(), effects=(parse_effect("sensor_location=0.008@3"),),
                     setup=setup, seed=seed)  # fmt: skip
    return rec, np.array(truth["effects"][0]["offsets"][0])


def test_offset_basis_is_the_plane_across_the_axis_or_every_axis():
    d = np.array([[0.3, -0.4, 0.866]])
    u = offset_basis(d)
    np.testing.assert_allclose(u @ u.T, np.eye(2), atol=1e-12)
    np.testing.assert_allclose(u @ d[0] / np.linalg.norm(d[0]), 0.0, atol=1e-12)
    np.testing.assert_array_equal(offset_basis(np.eye(3)), np.eye(3))


def test_the_offset_is_exact_on_noiseless_masslines(structure):
    """1e-8 noise: the offset read from a zero start is the concealed one to 1 µm (8 mm: 1e-4 relative)."""
    rec, offset = moved(structure, 1e-8)
    found = identify_recording(rec, (5.0, 95.0), draws=0)
    start = Finding("sensor_location", (2,), None, {"offset_m": [0.0, 0.0, 0.0]})
    read = read_offset(start, found)
    np.testing.assert_allclose(read.parameters["offset_m"], offset, atol=1e-6)
    assert read.parameters["distance_mm"] == pytest.approx(8.0, abs=1e-3)


@pytest.mark.parametrize("seed", [3, 4])
def test_diagnose_places_the_offset_and_reads_it_within_its_sigma(structure, seed):
    """1 % noise: one fault named, at the moved channel; named an offset, each component within 4σ of the truth
    (σ the length's); where a gain fits its four masslines as well (seed 4: ×0.63), the offset is its named
    alternative. The body after within 0.5 % in mass."""
    rec, offset = moved(structure, 0.01, seed)
    found = diagnose_recording(rec, (5.0, 95.0))
    faults = [f for f in found.findings if f.kind == "fault"]
    assert [f.channels for f in faults] == [(2,)], [(f.effect, f.channels) for f in faults]
    fault = faults[0]
    if fault.effect == "sensor_location":
        p = fault.parameters
        assert np.abs(1e3 * (np.array(p["offset_m"]) - offset)).max() < 4 * p["distance_std_mm"] + 0.05, p
    else:
        assert "sensor_location" in fault.evidence["alternatives"], fault
    assert found.mass == pytest.approx(structure.mass, rel=0.005)


def test_a_hits_offset_is_exact_on_noiseless_masslines(structure):
    """A hit landing 8 mm off its point (the second of four), 14 channels, 1e-8 noise: the offset read on
    identify's masslines from a zero start is the concealed one to 1 µm, and along the hit it reads none. (With
    the three hand-placed hits alone the other two give no body to start from, and the alternation from the
    body the moved hit bent stops at 2.4 mm.)"""
    rng = np.random.default_rng(2)
    sensors = Lines(rng.normal(size=(14, 3)) * 0.1, rng.normal(size=(14, 3)))
    three = structure_exciters()
    exciters = Lines(np.vstack([three.points, [[0.05, 0.12, 0.08]]]), np.vstack([three.directions, [[0.6, 0.8, 0]]]))
    rec, truth = run(structure, sensors, exciters, effects=(parse_effect("excitation_location=0.008@2"),),
                     setup=Acquisition(100.0, 100, Noise(1e-8, 0)), seed=3)  # fmt: skip
    offset = np.array(truth["effects"][0]["offsets"][0])
    found = identify_recording(rec, (5.0, 95.0), draws=0)
    read = read_offset(Finding("excitation_location", (), 1, {"offset_m": [0.0, 0.0, 0.0]}), found)
    np.testing.assert_allclose(read.parameters["offset_m"], offset, atol=1e-6)
    direction = exciters.directions[1] / np.linalg.norm(exciters.directions[1])
    assert np.dot(read.parameters["offset_m"], direction) == pytest.approx(0.0, abs=1e-9)
