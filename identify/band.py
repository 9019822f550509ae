"""Appendix A's zones found in the recording: A (suspension modes), B (the massline band), C (elastic modes).

A resonance shows in the FRF matrix as a run of frequencies where the
imaginary part dominates (the phase turns through 90° at every resonance of a
lightly damped mode, while the massline itself is real) or where the matrix
Re H(f) departs from its level in the quietest stretch (a resonance too narrow for the frequency
resolution still lifts or drops its neighbours). The band is the widest gap,
in log frequency, between such runs, kept clear of both sides by margins: the
band fit (:mod:`.massline_fit`) removes the tails of the suspension (∝ 1/ω²)
and of the elastic modes (∝ ω²), but not the peaks.
"""

from __future__ import annotations

import numpy as np

from massline.placement.band import Band
from massline.placement.errors import MasslineError

RESONANT = 0.5  # ‖Im H‖/‖H‖ above which a frequency is inside a resonance
OFF_LEVEL = 0.2  # ‖Re H(f) − H_quiet‖/‖H_quiet‖ that marks a disturbed line
ABOVE_SUSPENSION = 3.0  # band starts this many times above the top suspension resonance
BELOW_ELASTIC = 3.0  # and ends this many times below the first elastic resonance
MIN_LINES = 8


def imaginary_fraction(frf: np.ndarray) -> np.ndarray:
    """‖Im H(f)‖_F / ‖H(f)‖_F over all FRFs (n_s, n_e, n_f): near 0 on the massline, near 1 at resonances."""
    return np.linalg.norm(frf.imag, axis=(0, 1)) / np.maximum(np.linalg.norm(frf, axis=(0, 1)), 1e-300)


def runs_of(frequencies: np.ndarray, marked: np.ndarray) -> np.ndarray:
    """(k, 2) first and last frequency (Hz) of each run of marked lines."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], marked.astype(int), [0]]))).reshape(-1, 2)
    return np.column_stack([frequencies[edges[:, 0]], frequencies[edges[:, 1] - 1]])


def widest_gap(frequencies: np.ndarray, runs: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """Index of the widest log-frequency gap between runs; the gaps' lower and upper ends (Hz)."""
    f = frequencies
    tops = np.concatenate([[f[0] / ABOVE_SUSPENSION], runs[:, 1]])  # a resonance ends
    bottoms = np.concatenate([runs[:, 0], [f[-1] * BELOW_ELASTIC]])  # the next one starts
    return int(np.argmax(np.log(bottoms) - np.log(tops))), tops, bottoms


def log_spaced(frequencies: np.ndarray, where: np.ndarray, count: int = 200) -> np.ndarray:
    """Indices of lines spread evenly in log frequency over ``where`` (all lines if none):
    a median over them weighs each decade alike, not the top decade most as a linear axis does."""
    index = np.flatnonzero(where) if where.any() else np.arange(len(frequencies))
    f = frequencies[index]
    targets = np.geomspace(max(f[0], 1e-12), f[-1], count)
    return np.unique(index[np.clip(np.searchsorted(f, targets), 0, len(index) - 1)])


def disturbed(frequencies: np.ndarray, frf: np.ndarray) -> np.ndarray:
    """Lines inside a resonance: imaginary-dominated, or off the level of the quietest stretch."""
    phase = imaginary_fraction(frf) > RESONANT
    k, tops, bottoms = widest_gap(frequencies, runs_of(frequencies, phase))
    quiet = (frequencies > tops[k]) & (frequencies < bottoms[k])
    reference = np.median(frf.real[:, :, log_spaced(frequencies, quiet)], axis=2)
    departure = np.linalg.norm(frf.real - reference[:, :, None], axis=(0, 1)) / np.linalg.norm(reference)
    return phase | (departure > OFF_LEVEL)


def find_band(frequencies: np.ndarray, frf: np.ndarray) -> Band:
    """Zone B: the widest resonance-free stretch, with margins to the resonances on either side."""
    f = np.asarray(frequencies, dtype=float)
    runs = runs_of(f, disturbed(f, frf))
    k, tops, bottoms = widest_gap(f, runs)
    low, high = max(tops[k] * ABOVE_SUSPENSION, f[0]), min(bottoms[k] / BELOW_ELASTIC, f[-1])
    if np.count_nonzero((f >= low) & (f <= high)) < MIN_LINES:
        raise MasslineError(
            f"no massline band found: the widest resonance-free stretch is {tops[k]:.3g}–{bottoms[k]:.3g} Hz, "
            "too narrow once clear of its resonances; soften the suspension or give --band LO HI"
        )
    suspension = tops[k] if k > 0 else np.nan
    elastic = bottoms[k] if k < len(runs) else np.nan
    return Band(float(low), float(high), float(suspension), float(elastic), "found")


def given_band(frequencies: np.ndarray, low: float, high: float) -> Band:
    """The band the user gave (``--band LO HI``), checked against the recorded axis."""
    f = np.asarray(frequencies, dtype=float)
    if not 0 <= low < high:
        raise MasslineError(f"--band {low:g} {high:g}: give LO < HI in Hz")
    if np.count_nonzero((f >= low) & (f <= high)) < MIN_LINES:
        raise MasslineError(
            f"--band {low:g} {high:g} Hz holds fewer than {MIN_LINES} spectral lines of the recording "
            f"({f[0]:g}–{f[-1]:g} Hz): widen it"
        )
    return Band(float(low), float(high), np.nan, np.nan, "given")


def estimation_band(frequencies: np.ndarray, frf: np.ndarray, given: Band) -> Band:
    """The band identify would find for the properties; the diagnosis band when none is found (a support so
    stiff that no resonance-free stretch is clear of it)."""
    try:
        return find_band(frequencies, frf)
    except MasslineError:
        return given
