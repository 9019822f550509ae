"""The noise every fit is measured against comes from the recording, not from a fit of it.

The coherence route and the line-differences route each recover the simulated noise; a smooth systematic
departure (two channels lagging 120 µs, a mounting resonance) leaves them at the true noise where the residual of
the band fit (the old yardstick) grew with it; a fit below the noise and a recording noisier than its coherence
are warned; every real exporter's FRF gets a finite, sensible noise.
"""

from dataclasses import replace

import numpy as np
import pytest
from conftest import FIXTURE_UFF, bundled

from massline.identify.diagnose.pipeline import diagnose_recording
from massline.identify.pipeline import identify_recording
from massline.identify.recording_noise import above_coherence, below_noise, recording_noise, stated_averages
from massline.identify.tails import BandData
from massline.identify.warning_codes import codes_of
from massline.placement.hand_layouts import structure_exciters, structure_sensors
from massline.reports.identification_report import noise_note
from massline.uff.reader import read_uff
from massline.uff.writer import write_uff
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import Noise
from massline.virtual.suspension import Cord, Suspension

NOISE = 0.01  # the simulated relative noise
DELAY = 120e-6  # s: two channels on a second front end


@pytest.fixture(scope="module")
def clean():
    """The structure's hand layout (14 lines × 3 hits) on a soft cord, rigid, 1 % noise, 1000 lines to 250 Hz, and
    identify's band of it."""
    body = bundled("structure").nominal
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    setup = Acquisition(250.0, 1000, Noise(NOISE, 0.0), dc_line=False)
    recording, _ = run(body, structure_sensors(), structure_exciters(), None, cord, (), setup, 3)
    found = identify_recording(recording, draws=0)
    return recording, (found.band.low, found.band.high)


def delayed(recording, rows=(0, 3), tau=DELAY):
    """``recording`` with the FRFs of ``rows`` read e^{−iωτ} late, applied to the arrays directly."""
    frf = recording.frf.copy()
    frf[list(rows)] *= np.exp(-2j * np.pi * recording.frequencies * tau)
    return replace(recording, frf=frf)


def mounted(recording, row=5, f_m=600.0, zeta=0.03):
    """``recording`` with one channel read through a mounting resonance 1/(1 − (f/f_m)² + 2iζ f/f_m)."""
    r = recording.frequencies / f_m
    frf = recording.frf.copy()
    frf[row] /= 1 - r**2 + 2j * zeta * r
    return replace(recording, frf=frf)


def residual_noise(recording, band) -> float:
    """The old yardstick: the relative RMS of each FRF's own band fit (massline and free tails), its variance scaled
    by the residual's line correlation, √(Σ 2n σ² / Σ |H|²)."""
    data = BandData.from_recording(recording.frequencies, recording.frf, *band)
    lines = np.count_nonzero(data.lines, axis=2)
    return float(np.sqrt(np.sum(lines * data.noise**2) / np.sum(data.energy)))


def level(recording, band, coherence=True) -> float:
    found = recording_noise(recording.frequencies, recording.frf, recording.coherence if coherence else None, *band)
    return found.relative()


def test_both_routes_recover_the_simulated_noise(clean):
    recording, band = clean
    with_coherence = recording_noise(recording.frequencies, recording.frf, recording.coherence, *band)
    without = recording_noise(recording.frequencies, recording.frf, None, *band)
    assert with_coherence.method == "coherence" and without.method == "line differences"
    assert with_coherence.relative() == pytest.approx(NOISE, rel=0.03)
    assert without.relative() == pytest.approx(NOISE, rel=0.05)
    per_frf = without.differences / with_coherence.sigma  # each FRF's ~250 lines: a MAD's ~10 % scatter
    assert np.all(np.abs(per_frf - 1) < 0.3), per_frf


@pytest.mark.parametrize("departure", [delayed, mounted], ids=["two channels 120 µs late", "a mount at 600 Hz"])
def test_a_smooth_departure_leaves_the_noise_at_the_truth_where_the_fits_residual_grew(clean, departure):
    """Without coherence (the line-differences route) and with it, the noise stays within 5 % of the simulated
    1 %; the old yardstick, the band fit's own residual, takes the departure for noise."""
    recording, band = clean
    moved = departure(recording)
    assert residual_noise(recording, band) == pytest.approx(NOISE, rel=0.1)  # it was right on the clean file
    assert residual_noise(moved, band) > 1.3 * NOISE
    assert level(moved, band, coherence=False) == pytest.approx(NOISE, rel=0.05)
    assert level(moved, band) == pytest.approx(NOISE, rel=0.03)


def test_identify_states_the_noise_and_a_clean_fit_sits_at_it(clean):
    recording, _ = clean
    found = identify_recording(recording, draws=0)
    noise = found.payload["noise"]
    assert noise["method"] == "coherence" and noise["relative"] == pytest.approx(NOISE, rel=0.03)
    assert 0.9 < noise["fit_over_noise"] < 1.1
    assert not {"fit_below_noise", "noise_above_coherence"} & codes_of(found.warnings)
    said = f"noise: {100 * noise['relative']:.2f} % of the FRFs over the band (RMS, from the coherence)"
    assert said in noise_note(found)  # the identification report's band note


def test_the_diagnosis_measures_a_delayed_pair_of_channels_against_the_recordings_noise(clean):
    """Two channels 120 µs late: the diagnosis's noise is the recording's 1 %, and its fit after the tails is
    reported above it, where the old yardstick (the band fits' residual) put that fit inside the noise."""
    recording, _ = clean
    moved = delayed(recording)
    found = diagnose_recording(moved)
    after, noise = found.result.relative_rms("after"), found.result.noise
    assert found.document["fit"]["noise_method"] == "coherence" and noise == pytest.approx(NOISE, rel=0.03)
    assert after > 1.1 * noise
    band = (found.band.low, found.band.high)
    assert residual_noise(moved, band) > after  # the old yardstick: "within the noise"


def test_a_file_without_coherence_records_takes_the_line_differences(clean, tmp_path):
    recording, _ = clean
    path = tmp_path / "bare.uff"
    write_uff(path, replace(recording, coherence=None))
    found = identify_recording(path, draws=0)
    assert found.recording.coherence is None
    noise = found.payload["noise"]
    assert noise["method"] == "line differences" and noise["relative"] == pytest.approx(NOISE, rel=0.05)
    assert 0.9 < noise["fit_over_noise"] < 1.1


def test_a_fit_below_the_noise_and_noise_the_coherence_does_not_see_are_warned(clean):
    recording, band = clean
    noise = recording_noise(recording.frequencies, recording.frf, recording.coherence, *band)
    assert below_noise(noise, 0.85 * NOISE, "the fit") == []
    assert codes_of(below_noise(noise, 0.5 * NOISE, "the fit")) == {"fit_below_noise"}
    assert above_coherence(noise) == []
    told = recording.coherence ** (1 / 100)  # a coherence that claims 10× less noise than the lines show
    claimed = recording_noise(recording.frequencies, recording.frf, told, *band)
    assert codes_of(above_coherence(claimed)) == {"noise_above_coherence"}
    quiet = replace(noise, sigma=noise.sigma * 1e-3, differences=noise.differences * 1e-3)  # noiseless: not measurable
    assert below_noise(quiet, 0.0, "the fit") == [] and above_coherence(quiet) == []


def test_the_noise_is_stated_relative_to_the_frfs_a_fit_sees(clean):
    """Measured on the recording as it came, stated against FRFs moved first (a gauge's mass taken off each
    column): twice the FRFs, half the relative noise."""
    recording, band = clean
    noise = recording_noise(recording.frequencies, recording.frf, recording.coherence, *band)
    moved = noise.on(recording.frequencies, 2 * recording.frf, *band)
    assert moved.relative() == pytest.approx(noise.relative() / 2, rel=1e-12)
    np.testing.assert_array_equal(moved.sigma, noise.sigma)


def test_the_coherences_averages_scale_its_noise_as_the_header_states_them(clean):
    recording, band = clean
    one = recording_noise(recording.frequencies, recording.frf, recording.coherence, *band)
    five = recording_noise(recording.frequencies, recording.frf, recording.coherence, *band, averages=5)
    assert five.relative() == pytest.approx(one.relative() / np.sqrt(5), rel=1e-12)
    assert [stated_averages(h) for h in ("massline virtual test, H1 of 5 averages", "Averages: 10", "8 avg")] == [
        5, 10, 8]  # fmt: skip
    assert stated_averages("massline virtual test rig 3") == stated_averages("") == 1


def test_a_coherence_of_one_measures_nothing_and_the_differences_stand_in(clean):
    recording, band = clean
    ones = np.ones(recording.frf.shape)
    found = recording_noise(recording.frequencies, recording.frf, ones, *band)
    assert found.method == "line differences" and found.relative() == pytest.approx(NOISE, rel=0.05)


def test_hum_lines_do_not_lead_the_line_differences(clean):
    """Every 50 Hz line of every FRF 30 % off its massline: the median of the differences does not follow it."""
    recording, band = clean
    frf = recording.frf.copy()
    hum = np.isclose(recording.frequencies % 50.0, 0.0, atol=0.1)
    frf[:, :, hum] *= 1.3
    assert level(replace(recording, frf=frf), band, coherence=False) == pytest.approx(NOISE, rel=0.05)


FILES = sorted(p for p in FIXTURE_UFF.iterdir() if p.suffix in (".uff", ".unv"))


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_every_real_exporters_frf_gets_a_finite_noise_below_its_level(path):
    """Each FRF over its lines above 0 Hz: σ finite and positive, the relative noise below 1 (the FRF is not all
    noise), the coherence's where the file has it; files without FRFs hold nothing to measure."""
    for frf in read_uff(path).frfs:
        f, h = frf.frequencies, frf.accelerance
        top = f[f > 0]
        if len(top) < 12:  # a record of 6 lines holds no noise to measure
            continue
        coherence = None if frf.coherence is None else frf.coherence[None, None]
        found = recording_noise(f, h[None, None], coherence, top[0], top[-1])
        assert np.isfinite(found.sigma).all() and found.sigma.min() > 0, path.name
        assert 0 < found.relative() < 1, (path.name, found.relative())
        assert found.method == ("line differences" if frf.coherence is None else "coherence"), path.name


def test_a_real_impact_frf_with_its_coherence_gets_the_coherences_noise():
    """UFFFiles' impact FRF (0–800 Hz) beside its coherence record (a file of its own, read here with pyuff): the
    coherence's noise, finite and below the FRF's level; its line differences see less (a windowed record's
    neighbouring lines are alike), so nothing is warned."""
    import pyuff

    (record,) = [pyuff.UFF(str(FIXTURE_UFF / "ufffiles_dataset58_coh.unv")).read_sets()]
    frf = read_uff(FIXTURE_UFF / "ufffiles_dataset58_FRF.unv").frfs[0]
    n = len(frf.frequencies)
    gamma2 = np.real(record["data"][:n])
    f = frf.frequencies
    found = recording_noise(f, frf.accelerance[None, None], gamma2[None, None], f[1], f[-1])
    assert found.method == "coherence" and 0 < found.relative(found.differences) < found.relative() < 1
    assert above_coherence(found) == []
