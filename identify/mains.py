"""Mains interference found in a recording: lines at multiples of one frequency that stand out of most FRFs.

A ground loop adds the mains (50 or 60 Hz) and its harmonics to every response channel: in each H1 estimate a
narrow line, one or two spectral lines wide (more where an exponential window spreads it), with the mains'
phase rather than the FRF's. Left in, those lines are read as noise: they inflate the band fit's scatter, the
noise estimate and every χ² after it, while the masslines themselves barely move.

Each FRF's departure at a line from a smooth local fit, d = H(f) − H̃(f), H̃ the median of the WINDOW lines
on each side (real and imaginary parts apart: robust to the line's neighbour being part of the same spike),
is scaled by the FRF's local scatter, z = |d| / median |d| over the run of 2 SCATTER + 1 lines it falls in. Noise alone makes
|d| Rayleigh-distributed, so z > 3 on one FRF has probability exp(−(3·1.177)²/2) ≈ 2·10⁻³, and on most of
them at once none to speak of. A line *stands out* where the median of z over the FRFs exceeds SPIKE, where the FRFs are smooth (their
level varies by less than ROUGH across the fit's lines: no resonance) and the departures do not share one
phase: κ = |Σ d²| / Σ |d|² is 1 when every d_ij has one phase modulo π, as a mode narrower than a line gives
(its residues φ_i φ_j times one complex factor), and small for a hum, each channel with its own phase and each
hit at its own mains phase.

A fundamental f₀ explains the harmonics k f₀ whose lines (the one or two within a line spacing) stand out at
least faintly (FAINT: a few given lines are tested, not every line), one of them fully; it is found when it
explains at least MIN_HARMONICS, no sparser than one in DENSITY orders (a small f₀ has a harmonic near any
line), or when it is a mains frequency (50, 60 Hz) whose own line stands out. Candidates are the mains
frequencies and every standing-out line's frequency divided by 1, 2 and 3 (at least MIN_SPACINGS lines),
refined by least squares over the harmonics found (f_k = k f₀); the candidate explaining the most harmonics
wins, the highest among equals (f₀/2 explains the same lines). Set aside are the lines within a line spacing
of each harmonic found and the lines beside them that stand out as well (an exponential window's spread); a
harmonic too faint to stand out is left in (it adds less than the noise to its lines).

Each FRF is read on the lines it has (:mod:`.missing_lines`): its smooth fit is the median of its neighbours
present, a line it lacks has no departure (NaN: not one that stands out), and the medians and sums over FRFs
take those present at each line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.ndimage import maximum_filter1d, median_filter, minimum_filter1d

from massline.identify.missing_lines import mean_present, median_present, missing_as_nan, present

MAINS_HZ = (50.0, 60.0)  # the mains frequencies searched first
WINDOW = 4  # lines on each side of the smooth local fit
SCATTER = 25  # lines on each side of the local scatter
SPIKE = 3.0  # median over the FRFs of |d| / local scatter above which a line stands out
FAINT = 2.0  # the same for a harmonic of a fundamental found (a few lines tested, not every line)
ROUGH = 1.5  # the FRFs' local level varying more than this across the smooth fit's lines: a resonance
MIN_SPACINGS = 8  # the least fundamental, in line spacings (a smaller one has a harmonic near any line)
DENSITY = 3  # the highest harmonic found is at most this × the number found
PHASED = 0.8  # κ at or above which the departures share one phase (a mode), not a hum
MIN_HARMONICS = 2  # harmonics that must stand out for a fundamental to be found
MIN_FRFS = 4  # FRFs needed to tell a hum's phases from a mode's
DIVISORS = (1, 2, 3)  # a standing-out line may be the fundamental, its 2nd or its 3rd harmonic
REFINE = 2  # least-squares refinements of a candidate fundamental


@dataclass(frozen=True, eq=False)
class Departures:
    """Every FRF's departure from its smooth local fit at every line.

    Attributes
    ----------
    frequencies : (n,) array
        Hz.
    departure : (n_s, n_e, n) complex array
        d = H − H̃, (m/s²)/N; NaN at a line the FRF does not have.
    level : (n_s, n_e, n) array
        |H̃|, the FRF's local level, (m/s²)/N.
    score : (n,) array
        The median over FRFs of z = |d| / local scatter, dimensionless.
    phase_concentration : (n,) array
        κ = |Σ d²| / Σ |d|² over FRFs, 0–1.
    roughness : (n,) array
        The largest over the smallest RMS-over-FRFs level |H̃| across the WINDOW lines on each side: 1 on a
        massline, large across a resonance.
    """

    frequencies: np.ndarray
    departure: np.ndarray
    level: np.ndarray
    score: np.ndarray
    phase_concentration: np.ndarray
    roughness: np.ndarray

    @property
    def spacing(self) -> float:
        """The line spacing Δf, Hz (the median of the axis' steps)."""
        return float(np.median(np.diff(self.frequencies)))

    def outstanding(self, threshold: float = SPIKE) -> np.ndarray:
        """(n,) bool: lines that stand out of most FRFs (median z above ``threshold``) with no common phase, where
        the FRFs are smooth (no resonance)."""
        return (self.score > threshold) & (self.phase_concentration < PHASED) & (self.roughness < ROUGH)

    def near(self, tone: float) -> np.ndarray:
        """(n,) bool: the lines within one line spacing of ``tone`` Hz (one or two)."""
        return np.abs(self.frequencies - tone) < self.spacing * (1 - 1e-9)


def block_medians(values: np.ndarray, block: int) -> np.ndarray:
    """Each line's local scatter: the median of ``values`` (…, n) over the run of ``block`` lines it falls in
    (runs from the first line; the last one shorter), repeated over the run."""
    n = values.shape[-1]
    runs = -(-n // block)
    padded = np.full(values.shape[:-1] + (runs * block,), np.nan)
    padded[..., :n] = values
    medians = median_present(padded.reshape(values.shape[:-1] + (runs, block)), axis=-1)
    return np.repeat(medians, block, axis=-1)[..., :n]


def neighbour_median(values: np.ndarray) -> np.ndarray:
    """The median of the WINDOW lines on each side of every line (…, n) (itself left out; past an end of the axis,
    its end line), of those that are not NaN: the upper of two middle values, as scipy's median filter takes
    it; NaN where none is. Without NaN, scipy's median filter itself (the same values, faster)."""
    if not np.isnan(values).any():
        footprint = np.ones((1,) * (values.ndim - 1) + (2 * WINDOW + 1,), dtype=bool)
        footprint[..., WINDOW] = False
        return median_filter(values, footprint=footprint, mode="nearest")
    padded = np.pad(values, [(0, 0)] * (values.ndim - 1) + [(WINDOW, WINDOW)], mode="edge")
    neighbours = np.delete(sliding_window_view(padded, 2 * WINDOW + 1, axis=-1), WINDOW, axis=-1)
    ordered = np.sort(neighbours, axis=-1)  # NaN last
    middle = np.count_nonzero(~np.isnan(ordered), axis=-1) // 2
    return np.take_along_axis(ordered, middle[..., None], axis=-1)[..., 0]


def departures(frequencies: np.ndarray, frf: np.ndarray) -> Departures:
    """Each FRF's departure from the median of its WINDOW neighbours on each side, and the lines' scores."""
    has = present(frf)
    smooth = neighbour_median(missing_as_nan(frf.real, has)) + 1j * neighbour_median(missing_as_nan(frf.imag, has))
    d = missing_as_nan(frf - smooth, has)
    size = np.abs(d)
    scatter = block_medians(size, 2 * SCATTER + 1)
    z = size / np.maximum(scatter, 1e-300)
    score = median_present(z.reshape(-1, z.shape[2]), axis=0)
    squares = np.where(has, d, 0.0).reshape(-1, d.shape[2])  # a line an FRF lacks adds nothing to κ
    kappa = np.abs(np.sum(squares**2, axis=0)) / np.maximum(np.sum(np.abs(squares) ** 2, axis=0), 1e-300)
    level = np.sqrt(mean_present(np.abs(smooth.reshape(squares.shape)) ** 2, axis=0))
    span = 2 * WINDOW + 1
    roughness = maximum_filter1d(level, span, mode="nearest") / np.maximum(
        minimum_filter1d(level, span, mode="nearest"), 1e-300
    )
    return Departures(np.asarray(frequencies, dtype=float), d, np.abs(smooth), score, kappa, roughness)


def harmonics_found(found: Departures, fundamental: float) -> np.ndarray:
    """The orders k whose line(s) within a spacing of k f₀ stand out (faintly: a fundamental is given)."""
    f = found.frequencies[found.outstanding(FAINT)]
    k = np.rint(f / fundamental)
    return np.unique(k[(k >= 1) & (np.abs(f - k * fundamental) < found.spacing * (1 - 1e-9))]).astype(int)


def refined(found: Departures, fundamental: float) -> float:
    """f₀ by least squares over the harmonics found, f_k = k f₀, f_k the score-weighted centre of k's lines."""
    for _ in range(REFINE):
        orders = harmonics_found(found, fundamental)
        if len(orders) < MIN_HARMONICS:
            return fundamental
        centres = []
        for k in orders:
            lines = found.near(k * fundamental)
            centres.append(np.average(found.frequencies[lines], weights=found.score[lines]))
        fundamental = float(np.dot(orders, centres) / np.dot(orders, orders))
    return fundamental


def explains(found: Departures, fundamental: float) -> int:
    """How many harmonics of f₀ stand out, 0 unless they make its case: one standing out fully, and either
    MIN_HARMONICS of them, not sparser than one in DENSITY orders, or a mains frequency's own line."""
    orders = harmonics_found(found, fundamental)
    strong = found.outstanding()
    if not any(strong[found.near(k * fundamental)].any() for k in orders):
        return 0
    dense = len(orders) >= MIN_HARMONICS and DENSITY * len(orders) >= orders.max()
    mains = fundamental in MAINS_HZ and strong[found.near(fundamental)].any()
    return len(orders) if dense or mains else 0


def best_fundamental(found: Departures) -> float | None:
    """The candidate f₀ (Hz) explaining the most harmonics (the highest among equals), or None."""
    top, spacing = found.frequencies[-1], found.spacing
    standing = found.frequencies[found.outstanding()]
    candidates = {*MAINS_HZ, *(f / m for f in standing for m in DIVISORS)}
    scored = []
    for f0 in (f for f in candidates if MIN_SPACINGS * spacing <= f <= top):
        f0 = f0 if f0 in MAINS_HZ else refined(found, f0)
        scored.append((explains(found, f0), f0))
    count, f0 = max(scored, default=(0, None))
    return f0 if count else None


@dataclass(frozen=True, eq=False)
class MainsLines:
    """Mains interference found in a recording and the lines it sets aside.

    Attributes
    ----------
    fundamental : float
        f₀, Hz.
    harmonics : tuple of int
        The orders k whose lines stand out.
    amplitudes : tuple of float
        Each found harmonic's line relative to the FRFs' local level there (RMS over FRFs of the summed
        departures on its set-aside lines, over the RMS of |H̃|), dimensionless.
    scores : tuple of float
        Each found harmonic's score: the median over FRFs of its departure over the local scatter.
    aside : (n,) bool array
        The recording's lines set aside.
    frequencies : (n,) array
        The recording's lines, Hz.
    """

    fundamental: float
    harmonics: tuple
    amplitudes: tuple
    scores: tuple
    aside: np.ndarray
    frequencies: np.ndarray

    @property
    def lines_hz(self) -> list:
        """The set-aside lines' frequencies, Hz."""
        return self.frequencies[self.aside].tolist()

    @property
    def parameters(self) -> dict:
        """JSON-ready: the fundamental (Hz), the harmonics found, each one's and the largest relative amplitude,
        and the lines set aside (Hz)."""
        return {
            "fundamental_hz": self.fundamental,
            "harmonics": list(self.harmonics),
            "relative_amplitudes": list(self.amplitudes),
            "amplitude": max(self.amplitudes),
            "lines_hz": self.lines_hz,
        }

    @property
    def evidence(self) -> dict:
        """JSON-ready: how far each harmonic stands out (median over FRFs of |d| / local scatter; noise ≈ 1) and
        how many lines were set aside."""
        return {"median_z": list(self.scores), "lines_set_aside": int(self.aside.sum())}

    @property
    def note(self) -> str:
        """What identify says about it (a note, not a warning)."""
        orders = ", ".join(str(k) for k in self.harmonics)
        return (
            f"mains interference: {int(self.aside.sum())} lines at {self.fundamental:.4g} Hz × ({orders}) set aside "
            f"from every fit and the noise estimate (up to {max(self.amplitudes):.1%} of the FRFs' level)"
        )


def set_aside(found: Departures, fundamental: float) -> np.ndarray:
    """(n,) bool: the lines within a spacing of each harmonic found, and the lines within WINDOW of them that
    stand out too (a window's spread)."""
    aside = np.zeros(len(found.frequencies), dtype=bool)
    for k in harmonics_found(found, fundamental):
        aside |= found.near(k * fundamental)
    beside = np.convolve(aside, np.ones(2 * WINDOW + 1), mode="same") > 0
    return aside | (beside & found.outstanding(FAINT))


def harmonic_amplitude(found: Departures, lines: np.ndarray) -> float:
    """A harmonic's line relative to the FRFs' level: RMS over FRFs of Σ |d| over its lines, over RMS |H̃| (over
    the FRFs with some of its lines, each on those it has)."""
    has = ~np.isnan(found.departure[:, :, lines])
    seen = has.any(axis=2)
    summed = np.where(has, np.abs(found.departure[:, :, lines]), 0.0).sum(axis=2)[seen]
    level = np.where(has, found.level[:, :, lines], 0.0).max(axis=2)[seen]
    return float(np.sqrt(np.mean(summed**2) / np.maximum(np.mean(level**2), 1e-300)))


def find_mains(frequencies: np.ndarray, frf: np.ndarray) -> MainsLines | None:
    """Mains interference in the FRFs (n_s, n_e, n) on lines ``frequencies`` (n,) Hz above 0, or None: too few
    FRFs (with a line) or lines to tell, or no fundamental with MIN_HARMONICS standing out."""
    if np.count_nonzero(present(frf).any(axis=2)) < MIN_FRFS or len(frequencies) < 2 * SCATTER + 1:
        return None
    found = departures(frequencies, frf)
    fundamental = best_fundamental(found)
    if fundamental is None:
        return None
    orders = harmonics_found(found, fundamental)
    aside = set_aside(found, fundamental)
    amplitudes, scores = [], []
    for k in orders:
        near = found.near(k * fundamental)
        run = np.convolve(near, np.ones(2 * WINDOW + 1), mode="same") > 0
        amplitudes.append(harmonic_amplitude(found, run & aside))
        scores.append(float(found.score[near].max()))
    harmonics = tuple(int(k) for k in orders)
    return MainsLines(fundamental, harmonics, tuple(amplitudes), tuple(scores), aside, found.frequencies)
