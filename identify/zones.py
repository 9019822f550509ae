"""Appendix A's zones found in the recording: A (suspension modes), B (the massline band), C (elastic modes).

A resonance shows in the FRF matrix as a run of frequencies where the
imaginary part dominates (the phase turns through 90° at every resonance of a
lightly damped mode, while the massline itself is real) or where the matrix
Re H(f) departs from its level in the quietest stretch (a resonance too narrow for the frequency
resolution still lifts or drops its neighbours). The band is the widest gap,
in log frequency, between such runs, kept clear of both sides by margins: the
band fit (:mod:`.massline_fit`) removes the tails of the suspension (∝ 1/ω²)
and of the elastic modes (∝ ω²), but not the peaks.

Every measure reads the FRFs present at each line (:mod:`.missing_lines`): a pair not measured, or a line an
FRF on a coarser or shorter axis does not have, is left out of the norms, means and medians.
"""

from __future__ import annotations

import numpy as np

from massline.core.band import Band, GIVE_BAND
from massline.core.errors import MasslineError, param
from massline.identify.missing_lines import mean_present, median_present, missing_as_nan, pair_norm, present

RESONANT = 0.5  # ‖Im H‖/‖H‖ above which a frequency is inside a resonance
OFF_LEVEL = 0.2  # ‖Re H(f) − H_quiet‖/‖H_quiet‖ that marks a disturbed line
ABOVE_SUSPENSION = 3.0  # band starts this many times above the top suspension resonance
BELOW_ELASTIC = 3.0  # and ends this many times below the first elastic resonance
MIN_LINES = 8
FLAT = 0.5  # mean |d log|H| / d log f| below which a stretch reads a massline


def imaginary_fraction(frf: np.ndarray) -> np.ndarray:
    """‖Im H(f)‖_F / ‖H(f)‖_F over the FRFs (n_s, n_e, n_f) present at each line: near 0 on the massline, near 1
    at resonances."""
    has = present(frf)
    return pair_norm(frf.imag, has) / np.maximum(pair_norm(frf, has), 1e-300)


def runs_of(frequencies: np.ndarray, marked: np.ndarray) -> np.ndarray:
    """(k, 2) first and last frequency (Hz) of each run of marked lines."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], marked.astype(int), [0]]))).reshape(-1, 2)
    return np.column_stack([frequencies[edges[:, 0]], frequencies[edges[:, 1] - 1]])


def gaps_between(frequencies: np.ndarray, runs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper ends (Hz) of the stretches between runs: where a resonance ends, where the next starts."""
    f = frequencies
    tops = np.concatenate([[f[0] / ABOVE_SUSPENSION], runs[:, 1]])
    bottoms = np.concatenate([runs[:, 0], [f[-1] * BELOW_ELASTIC]])
    return tops, bottoms


def steepness(frequencies: np.ndarray, frf: np.ndarray, low: float, high: float) -> float:
    """Mean over FRFs of |d log|H| / d log f| across the middle half (in log f) of low–high.

    0 on a massline; 2 where the FRFs follow a stiffness line (below a stiff support's bounce, the lines
    it moves are spring-like while the others already read the mass). Each FRF's level at either end is from
    the lines it has there; the mean is over the FRFs with lines at both."""
    quarter = (high / low) ** 0.25
    ends = []
    for centre in (low * quarter, high / quarter):
        near = np.abs(np.log(frequencies / centre)) <= np.log(quarter) / 4
        if not near.any():
            return np.inf
        ends.append(np.sqrt(mean_present(np.abs(frf[:, :, near]) ** 2, axis=2)))  # |NaN| is NaN
    scale = np.maximum(ends[0], 1e-300)
    return float(mean_present(np.abs(np.log(np.maximum(ends[1], 1e-300) / scale))) / np.log(quarter**2))


def widest_gap(frequencies: np.ndarray, frf: np.ndarray, runs: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """Index of the widest log-frequency gap between runs where the FRFs are flat (mass-like); the gaps'
    lower and upper ends (Hz). A stiff support's bounce can leave a wider gap below it than above, where
    the FRFs it moves still follow a spring: flatness tells the massline's gap apart."""
    tops, bottoms = gaps_between(frequencies, runs)
    width = np.log(bottoms) - np.log(tops)
    if len(width) == 1:
        return int(np.argmax(width)), tops, bottoms
    low = np.maximum(tops, frequencies[0])
    high = np.minimum(bottoms, frequencies[-1])
    slope = np.array([steepness(frequencies, frf, lo, hi) if hi > lo * 1.5 else np.inf for lo, hi in zip(low, high)])
    flat = slope < FLAT
    candidates = np.flatnonzero(flat) if flat.any() else np.arange(len(width))
    return int(candidates[np.argmax(width[candidates])]), tops, bottoms


def log_spaced(frequencies: np.ndarray, where: np.ndarray, count: int = 200) -> np.ndarray:
    """Indices of lines spread evenly in log frequency over ``where`` (all lines if none):
    a median over them weighs each decade alike, not the top decade most as a linear axis does."""
    index = np.flatnonzero(where) if where.any() else np.arange(len(frequencies))
    f = frequencies[index]
    targets = np.geomspace(max(f[0], 1e-12), f[-1], count)
    return np.unique(index[np.clip(np.searchsorted(f, targets), 0, len(index) - 1)])


def disturbed(frequencies: np.ndarray, frf: np.ndarray) -> np.ndarray:
    """Lines inside a resonance: imaginary-dominated, or off the level of the quietest stretch (each FRF's median
    over its lines there; at each line, over the FRFs present with such a level)."""
    phase = imaginary_fraction(frf) > RESONANT
    k, tops, bottoms = widest_gap(frequencies, frf, runs_of(frequencies, phase))
    quiet = (frequencies > tops[k]) & (frequencies < bottoms[k])
    has, lines = present(frf), log_spaced(frequencies, quiet)
    reference = median_present(missing_as_nan(frf.real[:, :, lines], has[:, :, lines]), axis=2)
    seen = has & np.isfinite(reference)[:, :, None]
    level = pair_norm(np.broadcast_to(reference[:, :, None], frf.shape), seen)
    departure = pair_norm(frf.real - reference[:, :, None], seen) / np.maximum(level, 1e-300)
    return phase | (departure > OFF_LEVEL)


def stretch(frequencies: np.ndarray, frf: np.ndarray) -> Band:
    """The widest flat resonance-free stretch, edge to edge (no margins): where a band may be sought.

    Lines at or below 0 Hz (an exporter's DC line) are left out. ``suspension_top`` and ``first_elastic``
    are where the FRFs leave their massline below and above (nan on a side with no resonance in the record).
    """
    f = np.asarray(frequencies, dtype=float)
    above = f > 0
    f, frf = f[above], frf[:, :, above]
    runs = runs_of(f, disturbed(f, frf))
    k, tops, bottoms = widest_gap(f, frf, runs)
    suspension = tops[k] if k > 0 else np.nan
    elastic = bottoms[k] if k < len(runs) else np.nan
    return Band(float(tops[k]), float(bottoms[k]), float(suspension), float(elastic), "stretch")


def find_band(frequencies: np.ndarray, frf: np.ndarray) -> Band:
    """Zone B: the widest resonance-free stretch, with margins to the resonances on either side."""
    f = np.asarray(frequencies, dtype=float)
    f = f[f > 0]
    free = stretch(frequencies, frf)
    low, high = max(free.low * ABOVE_SUSPENSION, f[0]), min(free.high / BELOW_ELASTIC, f[-1])
    if np.count_nonzero((f >= low) & (f <= high)) < MIN_LINES:
        raise MasslineError(
            f"no massline band found: the widest resonance-free stretch is {free.low:.3g}–{free.high:.3g} Hz, "
            f"too narrow once clear of its resonances; soften the suspension or give {GIVE_BAND}"
        )
    return Band(float(low), float(high), free.suspension_top, free.first_elastic, "found")


def given(low: float, high: float) -> str:
    """The band a caller gave, as an error message names it (``band=(3, 40)``; the CLI's ``--band 3 40``)."""
    return param("band", f"({low:g}, {high:g})", cli=f"{low:g} {high:g}")


def given_band(frequencies: np.ndarray, low: float, high: float) -> Band:
    """The band the user gave (``--band LO HI``), checked against the recorded axis."""
    f = np.asarray(frequencies, dtype=float)
    if not 0 <= low < high:
        raise MasslineError(f"{given(low, high)}: give LO < HI in Hz")
    if np.count_nonzero((f >= low) & (f <= high)) < MIN_LINES:
        raise MasslineError(
            f"{given(low, high)} Hz holds fewer than {MIN_LINES} spectral lines of the recording "
            f"({f[0]:g}–{f[-1]:g} Hz): widen it"
        )
    return Band(float(low), float(high), np.nan, np.nan, "given")
