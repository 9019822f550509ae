"""FRFs with lines missing: NaN where a pair was not measured, or where an FRF on a coarser axis has no
line. The band fit, the band choice, the bounding modes, the mains search and the recording's warnings read each
FRF on its own lines: a pair left out changes nothing for the others, an FRF on every other line keeps its
massline with a larger ±, and nothing is warned because of a NaN.

The recordings are the structure's virtual test (the rigid body on a cord, 12 sensors × 6 hits, 1 % noise and
its coherence; no FE model), the same with a mains hum or from hammer hits, and test_resonances' modal sum of a
stiff support's modes and an elastic one (the support's top above the band, a shape to tell rigid).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from conftest import bundled
from test_resonances import HITS, SENSORS, E, S, modal_frf

from massline.core.band import Band
from massline.identify.band_choice import choose_band
from massline.identify.diagnose.effects import parse_effect
from massline.identify.line_correlation import variance_inflation
from massline.identify.mains import find_mains
from massline.identify.massline_fit import REAL, RICHER, WEIGHT_FLOOR, columns, fit_band
from massline.uff.runs import coherence_weights
from massline.identify.resonances import RIGID, bounding_modes, rigid_misfit
from massline.identify.suspicions import coherence_warnings, recording_warnings
from massline.placement.hand_layouts import structure_exciters, structure_origin_sensors, structure_sensors
from massline.uff.recording import Recording
from massline.virtual.acquisition import Acquisition, run
from massline.virtual.measurement import ImpactTest
from massline.virtual.suspension import Cord, Suspension

FIELDS = ("values", "std", "suspension", "flexibility", "quality", "bias", "truncation", "inflation")


def structure_test(effects: tuple = (), setup: Acquisition | None = None, seed: int = 2) -> Recording:
    """The structure on a cord, 12 sensors × 6 hits, recorded to 200 Hz in 2000 lines (or by ``setup``)."""
    body = bundled("structure").nominal
    cord = Suspension(cords=(Cord(body.cog + [0, 0, 0.02], body.mass * 9.81 / 0.25, 1.0),))
    sensors, hits = structure_sensors() + structure_origin_sensors(), structure_exciters(2)
    setup = setup or Acquisition(200.0, 2000, dc_line=False)
    return run(body, sensors, hits, None, cord, effects, setup, seed)[0]


@pytest.fixture(scope="module")
def clean() -> Recording:
    return structure_test()


@pytest.fixture(scope="module")
def hum() -> Recording:
    """The structure's test with a ground loop's hum, 10 % at 50 Hz and its harmonics, to 400 Hz."""
    return structure_test((parse_effect("mains_interference=0.1@50"),), Acquisition(400.0, 2000, dc_line=False))


@pytest.fixture(scope="module")
def modal() -> Recording:
    """Support modes up to a bounce at 80 Hz, an elastic mode at 170 Hz, 0.3 % noise; no coherence."""
    f = np.arange(0.25, 400.0, 0.25)
    H = modal_frf(f, [0.8, 1.0, 2.0, 3.0, 4.0, 80.0], 170.0)
    rng = np.random.default_rng(5)
    H = H + 0.003 * np.abs(H).mean() * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape))
    return Recording(f, H, SENSORS, HITS)


def masked(recording: Recording, has: np.ndarray) -> Recording:
    """``recording`` with NaN in its FRFs and coherence where ``has`` ((n_s, n_e) or (n_s, n_e, n_f)) is False."""
    has = np.broadcast_to(has if has.ndim == 3 else has[:, :, None], recording.frf.shape)
    coherence = None if recording.coherence is None else np.where(has, recording.coherence, np.nan)
    return replace(recording, frf=np.where(has, recording.frf, np.nan), coherence=coherence)


def dropped(recording: Recording, share: float = 0.05, seed: int = 4) -> np.ndarray:
    """(n_s, n_e) bool: the pairs kept when ``share`` of them are dropped at random."""
    has = np.ones(recording.frf.shape[:2], dtype=bool)
    rng = np.random.default_rng(seed)
    has.flat[rng.choice(has.size, size=max(1, round(share * has.size)), replace=False)] = False
    return has


def grown(recording: Recording) -> Recording:
    """``recording`` with one sensor and one hit more (copies of the first lines) that measured nothing."""
    frf = np.full(np.add(recording.frf.shape, (1, 1, 0)), np.nan + 0j)
    frf[:-1, :-1] = recording.frf
    coherence = None
    if recording.coherence is not None:
        coherence = np.full(frf.shape, np.nan)
        coherence[:-1, :-1] = recording.coherence
    sensors, hits = recording.sensors + recording.sensors[0], recording.exciters + recording.exciters[0]
    return replace(recording, frf=frf, coherence=coherence, sensors=sensors, exciters=hits)


def chosen(recording: Recording) -> Band:
    f, frf = recording.frequencies, recording.frf
    weights = coherence_weights(recording.coherence)
    return choose_band(f, frf, recording.sensors, recording.exciters, planar=False, weights=weights)


def edges(band: Band) -> np.ndarray:
    return np.array([band.low, band.high, band.suspension_top, band.first_elastic])


EPS = np.finfo(float).eps


def rounding(recording: Recording, band: Band, weighted: bool = True, richer: bool = False) -> tuple[float, float]:
    """How far two computations of the same band fits may differ when only their sums' rounding differs (their
    arrays' shapes, and so the order BLAS adds in), relative to a field's largest magnitude: (the refined fit's
    fields, the truncation shift).

    Each sum over the band's n lines is exact to n ε of its terms' size (γ_n), and the least squares carry that
    into the coefficients multiplied by the condition of what they solve: κ, the largest over the pairs of
    their (weighted) design [xᵐ] of Re H on the band's lines (Im H's, x^±1, is far better conditioned), for the
    fit refined from its residuals (to a QR fit's accuracy), and κ₀², the unweighted design's squared, for the
    truncation shift, which solves the unweighted normal equations. A pair's fit that read another pair's
    lines would move by that pair's data, many orders above either bound."""
    f = recording.frequencies
    keep = (f >= band.low) & (f <= band.high)
    omega = 2 * np.pi * f[keep]
    X = columns(omega**2 / (omega[0] * omega[-1]), REAL + (RICHER if richer else ())).T  # (n, k), as fit_band
    plain = np.linalg.cond(X)
    kappa = plain
    if weighted:
        w2 = np.nan_to_num(coherence_weights(recording.coherence)[:, :, keep]).reshape(-1, len(X))
        kappa = max(plain, np.linalg.cond(np.sqrt(np.maximum(w2, WEIGHT_FLOOR))[:, :, None] * X).max())
    return kappa * len(X) * EPS, plain**2 * len(X) * EPS


def assert_fits_agree(found, expected, bound: tuple[float, float], where=()):
    """Every field of two band fits within ``bound`` (:func:`rounding`) of its largest magnitude on the pairs
    ``where`` marks (all when empty): the same fits up to rounding."""
    for field in FIELDS:
        a, b = getattr(found, field)[where], getattr(expected, field)[where]
        tolerance = bound[1] if field == "truncation" else bound[0]
        np.testing.assert_allclose(a, b, rtol=0, atol=tolerance * np.abs(b).max(), err_msg=field)


# --- a complete recording: the pairs present read as without the missing ones --------------------------------------


@pytest.mark.parametrize("weighted", [True, False])
@pytest.mark.parametrize("richer", [False, True])
def test_a_pair_measured_by_nothing_changes_no_other_fit(clean, weighted, richer):
    """A sensor and a hit that measured nothing (NaN everywhere) leave every other pair's fit as it was: each
    FRF is fitted on its own; theirs is NaN in every field (complex NaN for the tails)."""
    band = chosen(clean)
    expected = fit_band(clean.frequencies, clean.frf, band.low, band.high,
                        coherence_weights(clean.coherence) if weighted else None, richer=richer)  # fmt: skip
    more = grown(clean)
    found = fit_band(more.frequencies, more.frf, band.low, band.high,
                     coherence_weights(more.coherence) if weighted else None, richer=richer)  # fmt: skip
    bound = rounding(clean, band, weighted, richer)
    assert_fits_agree(replace(found, **{k: getattr(found, k)[:-1, :-1] for k in FIELDS}), expected, bound)
    for field in FIELDS:
        nothing = np.concatenate([getattr(found, field)[-1], getattr(found, field)[:-1, -1]])
        assert np.isnan(nothing).all(), field


def test_the_band_modes_and_mains_of_a_complete_recording_ignore_a_pair_measured_by_nothing(clean, modal, hum):
    np.testing.assert_allclose(edges(chosen(grown(clean))), edges(chosen(clean)), rtol=1e-12)
    band = Band(20.0, 36.0, np.nan, np.nan, "found")
    more = grown(modal)
    expected = bounding_modes(modal.frequencies, modal.frf, band, modal.sensors, modal.exciters, False)
    assert expected == pytest.approx((80.0, 170.0), rel=0.01)
    assert bounding_modes(more.frequencies, more.frf, band, more.sensors, more.exciters, False) == expected
    before, after = find_mains(hum.frequencies, hum.frf), find_mains(hum.frequencies, grown(hum).frf)
    assert before.fundamental == after.fundamental == pytest.approx(50.0)
    assert after.harmonics == before.harmonics and np.array_equal(after.aside, before.aside)
    np.testing.assert_allclose(after.amplitudes, before.amplitudes, rtol=1e-12)
    np.testing.assert_allclose(after.scores, before.scores, rtol=1e-12)


# --- pairs not measured -------------------------------------------------------------------------------------------


def test_five_percent_of_pairs_dropped(clean):
    """4 of 72 pairs missing: the band within 10 % of the complete one's, the others' fits as they were (the same
    lines), the missing ones NaN."""
    has = dropped(clean)
    assert (~has).sum() == 4
    band, without = chosen(clean), chosen(masked(clean, has))
    np.testing.assert_allclose([without.low, without.high], [band.low, band.high], rtol=0.1)
    weights = coherence_weights(clean.coherence)
    expected = fit_band(clean.frequencies, clean.frf, band.low, band.high, weights)
    gappy = masked(clean, has)
    found = fit_band(gappy.frequencies, gappy.frf, band.low, band.high, coherence_weights(gappy.coherence))
    assert_fits_agree(found, expected, rounding(clean, band), has)
    for field in FIELDS:
        assert np.isnan(getattr(found, field)[~has]).all(), field
    unweighted = fit_band(gappy.frequencies, gappy.frf, band.low, band.high)
    expected = fit_band(clean.frequencies, clean.frf, band.low, band.high)
    assert_fits_agree(unweighted, expected, rounding(clean, band, weighted=False), has)


def test_a_missing_pair_leaves_the_support_and_elastic_modes(modal):
    """The shape of a peak is read on the pairs present: the bounce at 80 Hz still moves the body rigidly and the
    170 Hz mode does not."""
    band = Band(20.0, 36.0, np.nan, np.nan, "found")
    gappy = masked(modal, dropped(modal))
    found = bounding_modes(gappy.frequencies, gappy.frf, band, gappy.sensors, gappy.exciters, False)
    assert found == bounding_modes(modal.frequencies, modal.frf, band, modal.sensors, modal.exciters, False)


def test_a_shape_is_read_on_the_pairs_present():
    """One rigid motion seen on both sides stays rigid with a fifth of the pairs missing (the rank-one fit of the
    pairs present recovers it, to rounding: its misfit within n_s κ(S) ε, the least squares q = S⁺u's bound;
    the matrix with the missing pairs at 0 would give ~0.5); a shape no rigid motion gives stays elastic."""
    rng = np.random.default_rng(7)
    q = rng.normal(size=6)
    has = rng.random((len(S), len(E))) > 0.2
    rigid = np.where(has, 1j * np.outer(S @ q, E @ q), np.nan)
    assert rigid_misfit(rigid, S, E) < len(S) * np.linalg.cond(S) * EPS
    elastic = np.where(has, 1j * np.outer(rng.normal(size=len(S)), rng.normal(size=len(E))), np.nan)
    assert rigid_misfit(elastic, S, E) > 3 * RIGID


def test_a_hum_is_found_with_pairs_dropped(hum):
    complete = find_mains(hum.frequencies, hum.frf)
    found = find_mains(hum.frequencies, masked(hum, dropped(hum)).frf)
    assert found is not None and found.fundamental == pytest.approx(complete.fundamental, abs=0.01)
    assert 1 in found.harmonics


def test_a_clean_recording_with_lines_missing_names_no_hum(clean):
    """A line an FRF lacks is no departure from its neighbours: neither pairs dropped nor a column on every other
    line make a hum of their gaps."""
    for has in (dropped(clean, 0.2), on_every_other_line(clean, 2)):
        assert find_mains(clean.frequencies, masked(clean, has).frf) is None


# --- an FRF on a coarser axis ---------------------------------------------------------------------------------------


def on_every_other_line(recording: Recording, hit: int) -> np.ndarray:
    """(n_s, n_e, n_f) bool: every line, but only the even ones for the FRFs of ``hit``."""
    has = np.ones(recording.frf.shape, dtype=bool)
    has[:, hit, 1::2] = False
    return has


def test_a_hit_recorded_on_every_other_line_keeps_its_masslines_with_a_larger_sigma(clean):
    """The FRFs of hit 3 on every other line: each massline within 2σ (its own) of the complete fit's, from half
    the lines (σ about √2 larger: the lines' noise is white here); the other hits' fits as they were."""
    band = chosen(clean)
    coarse = masked(clean, on_every_other_line(clean, 2))
    assert np.allclose(edges(chosen(coarse)), edges(band), rtol=0.1, equal_nan=True)
    expected = fit_band(clean.frequencies, clean.frf, band.low, band.high, coherence_weights(clean.coherence))
    found = fit_band(coarse.frequencies, coarse.frf, band.low, band.high, coherence_weights(coarse.coherence))
    A, sigma = found.values[:, 2], found.std[:, 2]
    assert np.all(np.abs(A - expected.values[:, 2]) <= 2 * sigma), (A - expected.values[:, 2]) / sigma
    assert np.all(sigma > 1.2 * expected.std[:, 2]) and np.all(sigma < 1.7 * expected.std[:, 2])
    others = np.ones(found.values.shape, dtype=bool)
    others[:, 2] = False
    assert_fits_agree(found, expected, rounding(clean, band), others)


def test_the_line_correlation_of_an_frf_on_a_coarser_axis_is_over_its_own_lines():
    """A residual with lag-1 correlation on every other line of the axis: its inflation is the compact series'."""
    rng = np.random.default_rng(3)
    compact = np.zeros((50, 400))
    compact[:, 0] = rng.normal(size=50)
    for k in range(1, 400):
        compact[:, k] = 0.6 * compact[:, k - 1] + 0.8 * rng.normal(size=50)
    spread = np.full((50, 800), 1e3)  # what lies between the lines is never read
    spread[:, ::2] = compact
    has = np.zeros(spread.shape, dtype=bool)
    has[:, ::2] = True
    np.testing.assert_allclose(variance_inflation(spread, present=has), variance_inflation(compact), rtol=1e-12)


# --- warnings -------------------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def hammered() -> Recording:
    """An impact test: H1 over 2 hits, exponential window, the coherence (its roll-off, its short record)."""
    return structure_test(setup=Acquisition(impact=ImpactTest(averages=2)), seed=3)


def codes(found) -> set:
    return {w.code for w in found}


def test_no_warning_comes_from_a_nan(clean, hammered):
    """Pairs dropped or a hit on every other line: the recording's and the coherence's warnings are the complete
    recording's, or fewer; a band given close above the support is still warned, a poor FRF still present still
    named."""
    poor = clean.coherence.copy()
    poor[2, 1] = 0.5  # a double hit on one FRF
    faulty = replace(clean, coherence=poor)
    for recording in (clean, hammered, faulty):
        band = chosen(recording)
        given = Band(band.low, band.high, np.nan, np.nan, "given")
        near = Band(1.2 * band.suspension_top, band.high, np.nan, np.nan, "given")
        f = recording.frequencies
        in_band = (f >= band.low) & (f <= band.high)
        channels = [f"{i} / {j}" for i in range(recording.frf.shape[0]) for j in range(recording.frf.shape[1])]
        for has in (dropped(recording), on_every_other_line(recording, 2)):
            gappy = masked(recording, has)
            for b in (band, given, near):
                expected = recording_warnings(f, recording.frf, recording.coherence, b, recording.exponential_window)
                found = recording_warnings(f, gappy.frf, gappy.coherence, b, gappy.exponential_window)
                assert codes(found) <= codes(expected), (found, expected)
            assert "given_band_near_support" in codes(found)
            expected = coherence_warnings(recording.frf, recording.coherence, in_band, channels)
            found = coherence_warnings(gappy.frf, gappy.coherence, in_band, channels)
            assert codes(found) <= codes(expected), (found, expected)
            if recording is faulty and np.isfinite(gappy.frf[2, 1]).any():
                assert len(found) == 1 and "2 / 1" in found[0].text, found
