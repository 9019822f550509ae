"""Where the recording's resonances are: the support's top mode below the band, the first elastic mode above.

A resonance of the suspended body is a peak of the FRF matrix's imaginary part, s(f) = ‖Im H(f)‖_F over every
sensor and hit, standing out of the massline's level ‖Re H‖_F in the band (a massline is real). The peak's
line gives the mode's frequency to the line spacing, which is what the tail fits cannot: a pole fitted to a
tail inside the band is poorly determined (a support mode "near 1.3 Hz" for a bounce at 34 Hz). A frequency
is only given where the record holds the peak, fine enough that its line places the mode within 5 %
(Δf ≤ 5 % of it: a support mode 2 lines up the axis is anywhere between 1 and 3 lines); else nan.

Which kind a peak above the band is, its shape tells (:func:`rigid_misfit`): a support mode moves the body
rigidly, so that one rigid motion q explains both sides of the FRF matrix at its peak, the sensors' readings
S q and the hits' E q; an elastic mode does not. On a stiff support the band can lie below the bounce, and
the peak just above it is then the support's top mode, not the first elastic one (taken for it, it was
printed 51–90 % off on the blind suite's stiff cord). The hits' side is what tells the structure's first
elastic mode apart: its shape at the 14 sensors is within 5 % of a rigid motion, but not at the hits (45 %).

These are the frequencies identify's warnings and band, diagnose's findings and both reports quote
(:func:`bounding_modes`, :func:`support_and_elastic`): one rule, and nan where the record does not show them.

The norms are over the FRFs present at each line, scaled to all of them (:func:`.missing_lines.pair_norm`), and
a peak's shape is read on the pairs present at its line.
"""

from __future__ import annotations

import numpy as np

from massline.core.band import Band
from massline.core.lines import Lines
from massline.core.plate import plate_coordinates
from massline.identify.missing_lines import pair_norm, present

STANDS_OUT = 3.0  # a resonance's s(f) over the band's massline level
NEIGHBOURHOOD = 1.1  # a peak is the largest line within this factor in frequency either side
PRECISION = 0.05  # a mode's frequency is given when its peak's line places it within this fraction
RIGID = 0.12  # a peak whose shape one rigid motion fits within this is a support mode (blind suite, stiff
# cord: support modes ≤ 0.04 on clean records, 0.09 beside a hit's direction fault; elastic modes ≥ 0.17)
ALTERNATIONS = 50  # alternating least-squares steps of a shape's rank-one fit to the pairs present


def peak_curve(frf: np.ndarray) -> np.ndarray:
    """s(f) = ‖Im H(f)‖_F, (n_f,): the FRF matrix's imaginary part at every line (over the FRFs present)."""
    return pair_norm(frf.imag, present(frf))


def massline_level(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> float:
    """The median over the band's lines of ‖Re H(f)‖_F: the masslines' scale, (m/s²)/N."""
    inside = (frequencies >= band.low) & (frequencies <= band.high)
    return float(np.median(pair_norm(frf.real[:, :, inside], present(frf[:, :, inside]))))


def peaks(frequencies: np.ndarray, frf: np.ndarray, level: float) -> np.ndarray:
    """Lines (indices) where s(f) is the largest within NEIGHBOURHOOD either side and above STANDS_OUT × level."""
    s = peak_curve(frf)
    found = []
    for k in np.flatnonzero(s > STANDS_OUT * level):
        near = (frequencies >= frequencies[k] / NEIGHBOURHOOD) & (frequencies <= frequencies[k] * NEIGHBOURHOOD)
        if s[k] >= s[near].max():
            found.append(k)
    return np.array(found, dtype=int)


def resolved(frequencies: np.ndarray, k: int) -> bool:
    """Whether the peak at line k places its mode within PRECISION: a peak's line is the nearest to its mode
    (within Δf/2 of it, however narrow the peak), so it does when Δf ≤ PRECISION f_k; a peak on the record's
    first or last line may be the edge of one beyond it, and says nothing."""
    f = frequencies
    return bool(0 < k < len(f) - 1 and max(f[k] - f[k - 1], f[k + 1] - f[k]) <= PRECISION * f[k])


def leading_pair(values: np.ndarray, has: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The leading singular pair u (n_s,), v (n_e,) of ``values`` (n_s, n_e), unit vectors, fitted to the entries
    ``has`` marks: the SVD's when it marks all, else the rank-one least-squares fit u vᵀ to those entries alone,
    by ALTERNATIONS alternating steps from the SVD of the matrix with the others at 0 (0 on a row or column with
    none)."""
    filled = np.where(has, values, 0.0)
    U, s, Vt = np.linalg.svd(filled)
    if has.all():
        return U[:, 0], Vt[0]
    u, v, weight = U[:, 0], s[0] * Vt[0], has.astype(float)
    for _ in range(ALTERNATIONS):
        u = filled @ v / np.maximum(weight @ v**2, 1e-300)
        v = filled.T @ u / np.maximum(weight.T @ u**2, 1e-300)
    return u / max(np.linalg.norm(u), 1e-300), v / max(np.linalg.norm(v), 1e-300)


def rigid_misfit(frf_line: np.ndarray, S: np.ndarray, E: np.ndarray) -> float:
    """How far the resonance at one line (n_s, n_e) is from moving the body rigidly (0: rigid).

    u and v are the sensor and hit sides of Im H's leading singular pair, the mode's shape at the sensors
    and the hits; S (n_s, q) and E (n_e, q) the sensor and hit lines' coordinates. A rigid mode is q = S⁺u
    seen on both sides: the misfit is the mean of ‖(I − SS⁺)u‖ and the sine of the angle between v and E q
    (the mean, not the larger: one faulty channel or hit disturbs one side, an elastic shape both or one
    much more). Only the pairs present at the line count (:func:`leading_pair`), and the sensors and hits with
    one.

    The sine is the length of v's part across E q, ‖v − (e·v) e‖ with e = E q/‖E q‖ (v is a unit vector):
    accurate to rounding, where √(1 − cos²) is not below √ε ≈ 1.5e-8 (a cosine one ulp under 1 gives 2⁻²⁶), so
    an exactly rigid shape's misfit is ~κ(S) ε, whatever the last bit of the cosine.
    """
    has = present(frf_line)
    u, v = leading_pair(frf_line.imag, has)
    sensors, hits = has.any(axis=1), has.any(axis=0)
    u, v, S, E = u[sensors], v[hits], S[sensors], E[hits]
    q = np.linalg.lstsq(S, u, rcond=None)[0]
    at_hits = E @ q
    norm = np.linalg.norm(at_hits)
    if norm == 0:
        return 1.0
    e = at_hits / norm
    sine = min(1.0, float(np.linalg.norm(v - (e @ v) * e)))
    return float((np.linalg.norm(u - S @ q) + sine) / 2)


def support_and_elastic(
    frequencies: np.ndarray, frf: np.ndarray, band: Band, S: np.ndarray, E: np.ndarray
) -> tuple[float, float]:
    """(top support mode, first elastic mode), Hz, where the record resolves them; else nan.

    The support's modes are the peaks below the band and the rigid-shaped ones just above it (up to the
    first that is not); the elastic ones are the rest above the band. ``S``, ``E``: the sensor and hit lines'
    coordinates (:func:`rigid_misfit`).
    """
    f = np.asarray(frequencies, dtype=float)
    found = [k for k in peaks(f, frf, massline_level(f, frf, band)) if f[k] > 0]
    support = [k for k in found if f[k] < band.low]
    above = [k for k in found if f[k] > band.high]
    while above and rigid_misfit(frf[:, :, above[0]], S, E) < RIGID:
        support.append(above.pop(0))
    top = float(f[max(support)]) if support and resolved(f, max(support)) else np.nan
    first = float(f[above[0]]) if above and resolved(f, above[0]) else np.nan
    return top, first


def bounding_modes(
    frequencies: np.ndarray, frf: np.ndarray, band: Band, sensors: Lines, exciters: Lines, planar: bool
) -> tuple[float, float]:
    """(top support mode, first elastic mode), Hz, around ``band`` (:func:`support_and_elastic`), with the
    sensor and hit lines' coordinates of the recording's ``sensors`` and ``exciters`` (a plate's when
    ``planar``)."""
    S, E = (plate_coordinates(lines) if planar else lines.coordinates for lines in (sensors, exciters))
    return support_and_elastic(frequencies, frf, band, S, E)
