"""Mains interference (``mains_interference``): simulated, found, set aside, named.

On the three bundled bodies' lab tests (tests/lab_matrix.py: their plans, FE modes, a soft cord, 1 % noise, 3 %
transverse sensitivity, the exporter's recording), a ground loop's hum at 5, 10 and 20 % of the massline level
leaves the properties within 0.3σ of the clean file's (same seed, same lines), the reported noise
(the diagnosis's, over identify's band) and χ² within 20 % of the clean file's, and is named with its
fundamental; left in, the same hum inflates the noise. A clean file names no hum. The simulator refuses bad
values before any work.

The properties and χ² are compared with the clean file's on its band, with the same lines set aside: taking a
dozen of ~200 lines out moves an estimate by ~√(12/200) ≈ 0.25 of its σ whatever they held (the bracket's clean
file with the 20 % hum's lines taken out moved a moment 0.34σ and χ² 27 %), and what is measured is what the hum
leaves after its lines are set aside. The band identify chooses can differ once lines are set aside (the structure with 12 lines of 20 % hum at 60 Hz set aside chooses 38–156 Hz where the clean file
chose 38–209 Hz, and so does the clean file with the same 12 lines taken out: the choice's truncation-bias
term, D²/C, moves with any dozen lines), and on another band the properties differ by up to 1σ.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from lab_matrix import TRANSVERSE, acquisition, body_and_plan, support

from massline.cli.app import run as run_cli
from massline.core.errors import MasslineError
from massline.identify.recording_noise import recording_noise
from massline.identify.diagnose.effects import parse_effect
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.mains import find_mains
from massline.identify.pipeline import identify_recording
from massline.identify.tails import BandData
from massline.virtual.acquisition import run

HUMS = ("mains_interference=0.05@50", "mains_interference=0.1@50", "mains_interference=0.2@60")


def recorded(body: str, style: str = "exporter", hum: str | None = None):
    """The lab test of ``body`` on a soft cord (seed 0), with ``hum`` concealed."""
    mesh, sensors, exciters, modes = body_and_plan(body)
    effects = TRANSVERSE + ((parse_effect(hum),) if hum else ())
    return run(mesh.nominal, sensors, exciters, modes, support("soft", mesh, modes), effects, acquisition(style), 0)


def properties(found) -> tuple[np.ndarray, np.ndarray]:
    """Mass, CoG and the principal moments (a plate: its J_xx, J_yy) with their 1-σ; unobservable entries dropped."""
    b, s = found.body, found.std
    if found.planar:
        values = [b.mass, *b.cog[:2], b.inertia_cog[0, 0], b.inertia_cog[1, 1]]
        sigma = [s["mass"], *s["cog"][:2], s["inertia_cog"][0][0], s["inertia_cog"][1][1]]
    else:
        values, sigma = [b.mass, *b.cog, *b.principal_moments], [s["mass"], *s["cog"], *s["principal_moments"]]
    return np.array(values), np.array(sigma)


def noise(recording, found) -> float:
    """The recording's noise (its coherence's) over identify's band of ``recording``, relative RMS."""
    f, band = recording.frequencies, (found.band.low, found.band.high)
    return recording_noise(f, recording.frf, recording.coherence, *band).relative()


def fit_residual(recording, found) -> float:
    """The relative RMS of each FRF's own band fit (massline and free tails) over identify's band."""
    data = BandData.from_recording(recording.frequencies, recording.frf, found.band.low, found.band.high)
    return float(np.sqrt(np.sum(np.count_nonzero(data.lines, axis=2) * data.noise**2) / np.sum(data.energy)))


@pytest.fixture(scope="module", params=("bracket", "structure", "plate"))
def clean(request):
    recording, _ = recorded(request.param)
    return request.param, identify_recording(recording)


def test_a_clean_file_names_no_hum(clean):
    _, found = clean
    assert found.mains is None and not any("mains" in str(note) for note in found.notes)
    assert find_mains(found.recording.frequencies, found.recording.frf) is None


@pytest.mark.slow
@pytest.mark.parametrize("hum", HUMS)
def test_hum_is_named_set_aside_and_leaves_properties_and_noise(clean, hum):
    body, before = clean
    level, fundamental = (float(x) for x in hum.split("=")[1].split("@"))
    recording, _ = recorded(body, hum=hum)
    found = identify_recording(recording)
    assert found.mains is not None and abs(found.mains.fundamental - fundamental) < 0.5
    assert 1 in found.mains.harmonics and found.mains.amplitudes[0] == pytest.approx(level, rel=0.2)
    assert any(str(note).startswith("mains interference") for note in found.notes)
    assert found.payload["mains"]["fundamental_hz"] == found.mains.fundamental
    assert not any("mains" in str(warning) for warning in found.warnings)  # a note, not a warning
    band = (before.band.low, before.band.high)
    on_band = identify_recording(recording, band=band, draws=0)
    same_lines = identify_recording(before.recording.kept(~found.mains.aside), band=band, draws=0)
    values, _ = properties(on_band)
    reference, reference_sigma = properties(same_lines)
    assert np.all(np.abs(values - reference) <= 0.3 * reference_sigma), (values - reference) / reference_sigma
    clean_noise = noise(before.recording, before)
    assert noise(found.recording, found) == pytest.approx(clean_noise, rel=0.2)
    assert on_band.best.chi2 == pytest.approx(same_lines.best.chi2, rel=0.2)
    if level >= 0.2:  # left in, the hum is in the fits' residual, and the noise's median passes over it
        assert fit_residual(recording.above_zero(), before) > 1.2 * fit_residual(before.recording, before)
        assert noise(recording.above_zero(), before) == pytest.approx(clean_noise, rel=0.2)


@pytest.mark.slow
def test_diagnose_names_the_hum_as_test_physics():
    recording, _ = recorded("bracket", hum="mains_interference=0.1@50")
    diagnosis = diagnose_recording(recording)
    named = [f for f in diagnosis.document["findings"] if f["effect"] == "mains_interference"]
    assert len(named) == 1 and named[0]["kind"] == "test_physics"
    p = named[0]["parameters"]
    assert p["fundamental_hz"] == pytest.approx(50.0, abs=0.5) and p["harmonics"][0] == 1
    assert p["amplitude"] == pytest.approx(0.1, rel=0.2) and len(p["lines_hz"]) >= 2
    assert not [f for f in diagnosis.findings if f.kind == "fault"]
    assert any(w["code"] == "mains_set_aside" for w in diagnosis.document["warnings"])


@pytest.mark.long  # two 51,200-line hammer records: the long tier (the shaker's hums above cover the same search)
def test_an_impact_test_hum_is_found_and_set_aside():
    """H1 over 5 hits, each at its own mains phase: the hum's lines, spread by the exponential window."""
    clean_recording, _ = recorded("bracket", "impact")
    before = identify_recording(clean_recording)
    assert before.mains is None
    recording, _ = recorded("bracket", "impact", "mains_interference=0.1@50")
    found = identify_recording(recording)
    assert found.mains is not None and abs(found.mains.fundamental - 50.0) < 0.1 and 1 in found.mains.harmonics
    values, _ = properties(identify_recording(recording, band=(before.band.low, before.band.high), draws=0))
    reference, reference_sigma = properties(before)
    assert np.all(np.abs(values - reference) <= 0.3 * reference_sigma), (values - reference) / reference_sigma
    assert noise(found.recording, found) == pytest.approx(noise(before.recording, before), rel=0.2)


@pytest.mark.parametrize(
    "text, words",
    [
        ("mains_interference=-0.1@50", "positive fraction"),
        ("mains_interference=nan@50", "finite number"),
        ("mains_interference=0.1@-50", "positive number of Hz"),
        ("mains_interference=0.1@nan", "positive number of Hz"),
        ("mains_interference=0.1@fifty", "mains_interference=AMPLITUDE[@HZ]"),
        ("sensor_gain=nan@3", "finite"),
    ],
)
def test_bad_values_are_refused(text, words):
    with pytest.raises(MasslineError, match=words.replace("[", r"\[").replace("]", r"\]")):
        parse_effect(text)


def test_the_default_fundamental_is_50_hz():
    assert parse_effect("mains_interference=0.1").where == 50.0


def test_simulate_refuses_a_fundamental_outside_the_band_before_any_work(tmp_path, capsys):
    line = {"point": [0.0, 0.0, 0.0], "direction": [0.0, 0.0, 1.0], "triaxial": None}
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"sensors": [line] * 6, "exciters": [line]}))  # no mesh: the refusal comes first
    out = tmp_path / "test.uff"
    for effect, fmax in (("mains_interference=0.1@500", "400"), ("mains_interference=-1@50", "400")):
        code = run_cli(["simulate", str(plan), "--out", str(out), "--effect", effect, "--fmax", fmax])
        assert code == 2 and "mains_interference" in capsys.readouterr().err
    assert not out.exists()


def test_a_fundamental_outside_the_recorded_band_is_refused_by_the_virtual_test(bracket):
    from massline.placement.hand_layouts import structure_exciters
    from massline.core.lines import Lines
    from massline.virtual.acquisition import Acquisition

    sensors = Lines(np.eye(3) * 0.1, np.eye(3))
    setup = Acquisition(40.0, 400, dc_line=False)
    with pytest.raises(MasslineError, match="outside the recorded band"):
        run(bracket, sensors, structure_exciters(), effects=(parse_effect("mains_interference=0.1@50"),), setup=setup)


def test_simulate_help_documents_the_hum(capsys):
    assert run_cli(["simulate", "--help"], show_warnings=True) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "mains_interference=AMPLITUDE[@HZ]" in out and "default 50" in out and "massline level" in out
