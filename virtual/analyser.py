"""The analyser setup a test engineer chooses for an impact test, and what a setup given by hand truncates.

An impact test is set up around the band it is for (``notes/lab-realism.md`` §2):

* bandwidth: a few times the predicted band's top, rounded up to a bandwidth analysers offer (R10 steps:
  1, 1.25, 1.6, 2, 2.5, 3.2, 4, 5, 6.4, 8 × 10^k Hz); the first elastic mode may lie above it;
* record: the exponential window (``end`` at the record's end) adds σ_w = ln(1/end)/T to every pole. It
  leaves the massline unbiased but broadens the support modes; labs lengthen T before they window (§2, [S17]).
  The record is long enough when the window adds at most 5 % of critical damping to the lowest support mode:
  σ_w/ω_low ≤ 0.05, T ≥ ln(1/end)/(0.05·2π f_low) (≈ 15/f_low for a window to 1 %; the note's 6 time
  constants for a 0.5 % truncation error give the same order: 24 s for a 2 Hz mode at ζ = 2 %). The line count
  is the next of 400·2^k (401, 801, … 51201 values with the DC line), as analysers offer. The shortest record
  the band itself needs (``record="band"``) holds BAND_LINES lines between its edges, and the window adds at most
  5 % of critical damping at its low edge, where the support's tail is within the band's tolerance of the
  massline: the window's imaginary part there is 2σ_w/ω · (f_s/f)² of it, ≤ 0.1 % (1 s for the bracket's
  26–218 Hz, against 32 s for its 0.49 Hz pendulum mode; identify then says the support modes are unresolved);
* hammer tip: the half-sine pulse's spectrum 10 dB down at fmax (τ = 1.02/fmax: it excites the analysis band
  and little above it), and never more than 1 dB down at the band top (fτ ≤ 0.348); its first zero is at 1.5/τ.

A setup given by hand is kept, with a warning for each truncation: a record too short for the lowest support
mode by the rule above, or a pulse whose spectrum falls more than 3 dB inside the band (fτ > 0.594).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.band import Band

BANDWIDTH_FACTOR = 3.0  # fmax ≥ this × the band's top
R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.2, 4.0, 5.0, 6.4, 8.0)  # analyser bandwidths per decade
LINE_COUNTS = tuple(400 * 2**k for k in range(8))  # 400 … 51200 lines
ADDED_DAMPING = 0.05  # σ_w/ω of the lowest support mode the exponential window may add
PULSE_AT_FMAX = 1.02  # fτ where a half-sine's spectrum is 10 dB down
PULSE_AT_BAND_TOP = 0.348  # fτ where it is 1 dB down
PULSE_3DB = 0.594  # fτ where it is 3 dB down
FREE = 0.01  # Hz: support modes below this are free rigid motion (a yaw about a single cord)
RIGID_TOP = 100.0  # Hz: the least band top assumed for a rigid model
BAND_LINES = 100  # spectral lines between the band's edges in a record sized to the band
RECORDS = ("support", "band")  # what the record is long enough for: the lowest support mode, or the band


@dataclass(frozen=True)
class AnalyserSetup:
    """An impact test's acquisition.

    Attributes
    ----------
    fmax : float
        Bandwidth, Hz.
    lines : int
        Spectral lines: Δf = fmax/lines, record T = lines/fmax.
    pulse : float
        Half-sine pulse duration, s.
    needed_record : float
        The record the lowest support mode needs, s.
    warnings : tuple of str
        One sentence per truncation of a setting given by hand, with what to choose instead.
    """

    fmax: float
    lines: int
    pulse: float
    needed_record: float
    warnings: tuple[str, ...] = ()

    @property
    def record(self) -> float:
        """T = lines/fmax, s."""
        return self.lines / self.fmax


def band_top(band: Band) -> float:
    """The top of the band the test is for, Hz: its upper edge; for a rigid model (no top) a decade above its
    lower edge, and at least RIGID_TOP (a free body's band starts anywhere); where no line is predicted flat
    (a stiff support), half the first elastic mode: the engineer still records across the gap below it."""
    if np.isfinite(band.high):
        return float(band.high)
    if np.isnan(band.low) and np.isfinite(band.first_elastic):
        return 0.5 * float(band.first_elastic)
    return max(10.0 * float(np.nan_to_num(band.low)), RIGID_TOP)


def lowest_support_mode(support_hz: np.ndarray) -> float:
    """The lowest support mode above free motion, Hz; inf on a free body."""
    modes = np.asarray(support_hz, dtype=float)
    modes = modes[modes > FREE]
    return float(modes.min()) if len(modes) else np.inf


def needed_record(f_low: float, window_end: float) -> float:
    """T (s) for which the exponential window adds ADDED_DAMPING of critical damping at f_low (Hz); 0 if f_low is
    inf (a free body: nothing for the window to broaden)."""
    return float(np.log(1 / window_end) / (ADDED_DAMPING * 2 * np.pi * f_low))


def band_record(band: Band, top: float, window_end: float) -> float:
    """T (s) the band needs: BAND_LINES lines between its edges, the window adding at most ADDED_DAMPING of
    critical damping at its low edge; nan when the band has no low edge (a rigid model's, a stiff support's)."""
    if not np.isfinite(band.low) or band.low <= 0 or top <= band.low:
        return np.nan
    return max(needed_record(float(band.low), window_end), BAND_LINES / (top - float(band.low)))


def r10_steps(near: float) -> list[float]:
    """The R10 bandwidths (Hz) of the decades around ``near``, ascending."""
    decade = float(10.0 ** np.floor(np.log10(near)))
    return [step * scale for scale in (decade / 10, decade, 10 * decade) for step in R10]


def analyser_bandwidth(top: float) -> float:
    """The smallest R10 bandwidth at or above BANDWIDTH_FACTOR × ``top`` (Hz)."""
    target = BANDWIDTH_FACTOR * top
    return next(f for f in r10_steps(target) if f >= target * (1 - 1e-9))


def max_bandwidth(record: float) -> float:
    """The largest R10 bandwidth (Hz) whose longest line count still holds ``record`` s."""
    limit = LINE_COUNTS[-1] / record
    return max(f for f in r10_steps(limit) if f <= limit * (1 + 1e-9))


def line_count(fmax: float, record: float) -> int:
    """The smallest of LINE_COUNTS whose record lines/fmax is at least ``record`` s (the largest if none)."""
    return next((n for n in LINE_COUNTS if n / fmax >= record), LINE_COUNTS[-1])


def hammer_pulse(fmax: float, top: float) -> float:
    """Half-sine duration (s): 10 dB down at fmax, at most 1 dB down at the band top (Hz)."""
    return float(min(PULSE_AT_FMAX / fmax, PULSE_AT_BAND_TOP / top))


def impact_setup(
    band: Band,
    support_hz: np.ndarray,
    window_end: float,
    fmax: float | None = None,
    lines: int | None = None,
    pulse: float | None = None,
    record: str = "support",
) -> AnalyserSetup:
    """The setup for ``band`` (predicted), with what was given by hand kept and its truncations said.

    Parameters
    ----------
    band : Band
        The predicted massline band, Hz.
    support_hz : array
        The support (suspension) modes, Hz.
    window_end : float
        The exponential window's value at the end of the record.
    fmax, lines, pulse : float, int, float or None
        Bandwidth (Hz), spectral lines and pulse duration (s) given by hand; None: chosen.
    record : {"support", "band"}
        The record long enough for the lowest support mode, or the shortest the band needs (:func:`band_record`;
        the support's rule where the band has no low edge).
    """
    top, f_low, what = band_top(band), lowest_support_mode(support_hz), "the lowest support mode"
    fmax = float(fmax or analyser_bandwidth(top))
    needed = band_record(band, top, window_end) if record == "band" else np.nan
    if np.isnan(needed):
        needed = needed_record(f_low, window_end)
    else:
        f_low, what = float(band.low), "the band's low edge"
    chosen_lines = line_count(fmax, needed)
    chosen_pulse = hammer_pulse(fmax, top)
    warnings = []
    length = (lines or chosen_lines) / fmax
    if length < needed:
        added = np.log(1 / window_end) / length / (2 * np.pi * f_low)
        fits = chosen_lines / fmax >= needed
        instead = (
            f"--lines {chosen_lines}"
            if fits
            else f"--fmax {max_bandwidth(needed):g} --lines {LINE_COUNTS[-1]}, or leave both out"
        )
        warnings.append(
            f"a record of {length:.3g} s ({lines or chosen_lines} lines to {fmax:g} Hz) is too short for {what} "
            f"at {f_low:.2g} Hz: the exponential window adds {added:.0%} of critical damping to it "
            f"(T ≥ {needed:.3g} s keeps it to {ADDED_DAMPING:.0%}); choose {instead}"
        )
    if pulse and top * pulse > PULSE_3DB:
        drop = -20 * np.log10(max(abs(np.cos(np.pi * top * pulse) / (1 - 4 * (top * pulse) ** 2)), 1e-6))
        warnings.append(
            f"a {pulse * 1e3:.3g} ms pulse's spectrum falls {drop:.0f} dB by the band top ({top:.4g} Hz; −3 dB at "
            f"{PULSE_3DB / pulse:.4g} Hz): choose --impact {chosen_pulse * 1e3:.2g} or shorter"
        )
    return AnalyserSetup(fmax, lines or chosen_lines, pulse or chosen_pulse, needed, tuple(warnings))
