"""Where the recording's resonances are: the support's top mode below the band, the first elastic mode above.

A resonance of the suspended body is a peak of the FRF matrix's imaginary part, s(f) = ‖Im H(f)‖_F over every
sensor and hit, standing out of the massline's level ‖Re H‖_F in the band (a massline is real). The peak's
line gives the mode's frequency to the line spacing, which is what the tail fits cannot: a pole fitted to a
tail inside the band is poorly determined (a support mode "near 1.3 Hz" for a bounce at 34 Hz). A frequency
is only given where the record holds the peak; else nan.
"""

from __future__ import annotations

import numpy as np

from massline.placement.band import Band

STANDS_OUT = 3.0  # a resonance's s(f) over the band's massline level
NEIGHBOURHOOD = 1.1  # a peak is the largest line within this factor in frequency either side


def peak_curve(frf: np.ndarray) -> np.ndarray:
    """s(f) = ‖Im H(f)‖_F, (n_f,): the FRF matrix's imaginary part at every line."""
    return np.linalg.norm(frf.imag, axis=(0, 1))


def massline_level(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> float:
    """The median over the band's lines of ‖Re H(f)‖_F: the masslines' scale, (m/s²)/N."""
    inside = (frequencies >= band.low) & (frequencies <= band.high)
    return float(np.median(np.linalg.norm(frf.real[:, :, inside], axis=(0, 1))))


def peaks(frequencies: np.ndarray, frf: np.ndarray, level: float) -> np.ndarray:
    """Lines (indices) where s(f) is the largest within NEIGHBOURHOOD either side and above STANDS_OUT × level."""
    s = peak_curve(frf)
    found = []
    for k in np.flatnonzero(s > STANDS_OUT * level):
        near = (frequencies >= frequencies[k] / NEIGHBOURHOOD) & (frequencies <= frequencies[k] * NEIGHBOURHOOD)
        if s[k] >= s[near].max():
            found.append(k)
    return np.array(found, dtype=int)


def resolved(frf: np.ndarray, k: int) -> bool:
    """Whether the peak at line k is resolved: both neighbouring lines above half its height (a peak narrower
    than the line spacing, or cut by the record's edge, does not say where its mode is)."""
    s = peak_curve(frf)
    return bool(0 < k < len(s) - 1 and min(s[k - 1], s[k + 1]) >= s[k] / 2)


def support_top(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> float:
    """The highest resonance below the band (Hz; nan when the record shows none or does not resolve it)."""
    f = np.asarray(frequencies, dtype=float)
    found = [k for k in peaks(f, frf, massline_level(f, frf, band)) if 0 < f[k] < band.low]
    return float(f[max(found)]) if found and resolved(frf, max(found)) else np.nan


def first_elastic(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> float:
    """The lowest resonance above the band (Hz; nan when the record ends before one or does not resolve it)."""
    f = np.asarray(frequencies, dtype=float)
    found = [k for k in peaks(f, frf, massline_level(f, frf, band)) if f[k] > band.high]
    return float(f[min(found)]) if found and resolved(frf, min(found)) else np.nan
