"""Mains hum: a ground loop in the accelerometer cables adds the mains voltage to every response channel.

The hum is a disturbance on the response channels, uncorrelated with the force: X = H F + M. In an H1
estimate it adds M F*/|F|² at the mains fundamental f₀ and its harmonics k f₀, with the phase of the mains
at each record (not the FRF's), and the coherence drops there (:func:`massline.virtual.measurement.noisy_frfs`):

    γ² = |H|² / (|H|² + σ² + |h|²).

A ground loop's hum is distorted (a transformer's or rectifier's current), so its odd harmonics dominate: the
k-th at 1/k of the fundamental, the even ones ten times weaker (``harmonic_levels``). Its size is given as the
fundamental's line relative to each channel's massline level (the RMS over the hits of the channel's
massline, so every FRF of a channel carries the same hum, as one cable does). The channel's hum keeps one
phase θ_i per harmonic; each hit (exciter) starts at its own mains phase φ_j, so h_ij = |h_i| e^{i(θ_i + φ_j)}.

Direct route: a tone between two spectral lines shows on both, shared linearly by its distance to each
(``line_shares``): one or two lines wide. Impact route: the tone is added in time to each hit's response
record, at the mains phase of that hit (:func:`hum_records`); the exponential window spreads it over a few
lines and averaging n hits of random mains phase lowers it by about √n.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError

EVEN = 0.1  # an even harmonic's level relative to an odd one of the same order


@dataclass(frozen=True)
class Hum:
    """A ground loop's mains hum on every response channel.

    Attributes
    ----------
    fundamental : float
        The mains frequency f₀, Hz (50 or 60 in a lab).
    level : float
        The fundamental's line in the FRFs, a fraction of each channel's massline level.
    """

    fundamental: float
    level: float

    def harmonics(self, fmax: float) -> np.ndarray:
        """The orders k = 1, 2, … with k f₀ ≤ fmax (Hz)."""
        return np.arange(1, int(np.floor(fmax / self.fundamental * (1 + 1e-12))) + 1)


def harmonic_levels(k: np.ndarray) -> np.ndarray:
    """Each harmonic's level relative to the fundamental: 1/k for odd k, EVEN/k for even k."""
    k = np.asarray(k, dtype=float)
    return np.where(k % 2 == 1, 1.0, EVEN) / k


def check_fundamental(fundamental: float, low: float, high: float) -> None:
    """Refuse a mains fundamental (Hz) outside the recorded band ``low``–``high`` (Hz: Δf to fmax)."""
    if not low <= fundamental <= high:
        raise MasslineError(
            f"effect mains_interference: its fundamental {fundamental:g} Hz lies outside the recorded band "
            f"({low:g}–{high:g} Hz): give a mains frequency inside it (50 or 60 Hz) or change --fmax/--lines"
        )


def check_hum(hums, frequencies: np.ndarray) -> None:
    """Refuse a hum whose fundamental lies outside the recorded lines above 0 Hz (``frequencies``, Hz)."""
    above = frequencies[frequencies > 0]
    for hum in hums:
        check_fundamental(hum.fundamental, float(above[0]), float(above[-1]))


def line_shares(frequencies: np.ndarray, tone: float) -> np.ndarray:
    """How a tone at ``tone`` Hz shows on evenly spaced lines (n,): shared between its two nearest lines by
    its distance to each (1 on a line it falls on), 0 elsewhere."""
    df = frequencies[1] - frequencies[0]
    position = (tone - frequencies[0]) / df
    below = int(np.floor(position))
    share = np.zeros(len(frequencies))
    for line, weight in ((below, 1 - (position - below)), (below + 1, position - below)):
        if 0 <= line < len(frequencies):
            share[line] += weight
    return share


def channel_levels(masslines: np.ndarray) -> np.ndarray:
    """Each channel's massline level (n_s,): the RMS over the hits of its masslines, (m/s²)/N."""
    return np.sqrt(np.mean(masslines**2, axis=1))


def hum_lines(
    frequencies: np.ndarray, hum: Hum, levels: np.ndarray, n_exciters: int, rng: np.random.Generator
) -> np.ndarray:
    """The hum's part of every H1 estimate, (n_s, n_e, n) (m/s²)/N: h_ij = level_i c_k e^{i(θ_ik + φ_jk)} on the
    lines of each harmonic k (``line_shares``), c_k its ``harmonic_levels``."""
    k = hum.harmonics(frequencies[-1])
    shares = np.array([line_shares(frequencies, order * hum.fundamental) for order in k])  # (n_k, n)
    theta = rng.uniform(0, 2 * np.pi, size=(len(levels), 1, len(k)))
    phi = rng.uniform(0, 2 * np.pi, size=(1, n_exciters, len(k)))
    sizes = hum.level * levels[:, None, None] * harmonic_levels(k) * np.exp(1j * (theta + phi))
    return sizes @ shares


def with_hum(
    frequencies: np.ndarray,
    frf: np.ndarray,
    coherence: np.ndarray,
    hums,
    masslines: np.ndarray,
    rng: np.random.Generator,
) -> tuple[np.ndarray, np.ndarray]:
    """The direct route's FRFs (n_s, n_e, n) with every hum added, and their coherence dropped by it:
    1/γ² grows by |h|²/|H|² (an H1 estimate's error variance grows by the hum's power)."""
    for hum in hums:
        h = hum_lines(frequencies, hum, channel_levels(masslines), frf.shape[1], rng)
        power = np.maximum(np.abs(frf) ** 2, 1e-300)
        coherence = 1 / (1 / np.maximum(coherence, 1e-300) + np.abs(h) ** 2 / power)
        frf = frf + h
    return frf, coherence


@dataclass(frozen=True)
class Tones:
    """The hum's tones on the response channels of an impact test.

    Attributes
    ----------
    frequencies : (m,) array
        Every harmonic of every hum, Hz.
    orders : (m,) int array
        Each tone's order k (its phase turns k times the mains phase).
    amplitudes, phases : (n_s, m) arrays
        Each channel's tone amplitude (m/s²) and its own phase θ (rad).
    """

    frequencies: np.ndarray
    orders: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray

    def record(self, t: np.ndarray, mains_phase: float) -> np.ndarray:
        """One hit's hum (n_s, n) m/s² at times ``t`` (s), the mains at ``mains_phase`` (rad) when it starts."""
        out = np.zeros((len(self.amplitudes), len(t)))
        for f, k, a, theta in zip(self.frequencies, self.orders, self.amplitudes.T, self.phases.T):
            out += a[:, None] * np.cos(2 * np.pi * f * t[None] + k * mains_phase + theta[:, None])
        return out


def impact_tones(hums, levels: np.ndarray, force_line, window_sum: float, fmax: float, rng) -> Tones:
    """The tones whose windowed spectrum makes one record's H1 line level_i c_k: a tone a cos(2π f t + θ) has
    a Σw/2 on its line, so a = 2 level_i c_k |F(f)| / Σw (``window_sum`` Σw, ``force_line(f)`` the windowed
    force's |F| on the line nearest f, N·s per sample)."""
    parts = []
    for hum in hums:
        for order in hum.harmonics(fmax):
            f = order * hum.fundamental
            amplitude = 2 * hum.level * levels * harmonic_levels(order) * force_line(f) / window_sum
            parts.append((f, order, amplitude, rng.uniform(0, 2 * np.pi, size=len(levels))))
    if not parts:
        return Tones(np.zeros(0), np.zeros(0, int), np.zeros((len(levels), 0)), np.zeros((len(levels), 0)))
    f, k, a, theta = zip(*parts)
    return Tones(np.array(f), np.array(k), np.stack(a, axis=1), np.stack(theta, axis=1))
