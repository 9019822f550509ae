"""Where the recording's resonances are: the support's top mode below the band, the first elastic mode above.

A resonance of the suspended body is a peak of the FRF matrix's imaginary part, s(f) = ‖Im H(f)‖_F over every
sensor and hit, standing out of the massline's level ‖Re H‖_F in the band (a massline is real). The peak's
line gives the mode's frequency to the line spacing, which is what the tail fits cannot: a pole fitted to a
tail inside the band is poorly determined (a support mode "near 1.3 Hz" for a bounce at 34 Hz). A frequency
is only given where the record holds the peak; else nan.

Which kind a peak is, its shape at the sensors tells (:func:`rigid_shaped`): a support mode moves the body
rigidly, an elastic mode does not. On a stiff support the band can lie between support modes, and the peak
just above it is then the top support mode, not the first elastic one (taken for it, it was printed 53 %
low).
"""

from __future__ import annotations

import numpy as np

from massline.placement.band import Band
from massline.placement.lines import Lines
from massline.placement.plate import plate_coordinates

STANDS_OUT = 3.0  # a resonance's s(f) over the band's massline level
NEIGHBOURHOOD = 1.1  # a peak is the largest line within this factor in frequency either side
RIGID_SHAPE = 0.2  # a mode shape at the sensors this close to a rigid motion is a support mode


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


def rigid_shaped(frf_line: np.ndarray, sensors: Lines, planar: bool) -> bool | None:
    """Whether the resonance at one line (n_s, n_e) moves the body rigidly: the sensor side of Im H's leading
    singular pair, its mode shape at the sensors, lies in the span of the sensor lines' coordinates (n_s × q)
    within RIGID_SHAPE; None when the layout cannot tell (no more sensor lines than q)."""
    S = plate_coordinates(sensors) if planar else sensors.coordinates
    if len(sensors) <= S.shape[1]:
        return None
    shape = np.linalg.svd(frf_line.imag)[0][:, 0]
    Q, _ = np.linalg.qr(S)
    return bool(np.linalg.norm(shape - Q @ (Q.T @ shape)) < RIGID_SHAPE)


def support_top(frequencies: np.ndarray, frf: np.ndarray, band: Band, sensors: Lines, planar: bool) -> float:
    """The highest support resonance (Hz): the highest rigid-shaped peak below the first elastic one, or the
    highest peak below the band where the shapes cannot tell; nan when the record shows none or does not
    resolve it."""
    f = np.asarray(frequencies, dtype=float)
    found = [k for k in peaks(f, frf, massline_level(f, frf, band)) if f[k] > 0]
    kinds = {k: rigid_shaped(frf[:, :, k], sensors, planar) for k in found}
    if any(kind is None for kind in kinds.values()):
        below = [k for k in found if f[k] < band.low]
    else:
        elastic = min((f[k] for k in found if not kinds[k]), default=np.inf)
        below = [k for k in found if kinds[k] and f[k] < elastic]
    return float(f[max(below)]) if below and resolved(frf, max(below)) else np.nan


def first_elastic(frequencies: np.ndarray, frf: np.ndarray, band: Band, sensors: Lines, planar: bool) -> float:
    """The lowest elastic resonance above the band (Hz): the lowest peak above it that is not rigid-shaped; nan
    when the record ends before one or does not resolve it."""
    f = np.asarray(frequencies, dtype=float)
    found = [k for k in peaks(f, frf, massline_level(f, frf, band)) if f[k] > band.high]
    elastic = [k for k in found if not rigid_shaped(frf[:, :, k], sensors, planar)]
    return float(f[min(elastic)]) if elastic and resolved(frf, min(elastic)) else np.nan
