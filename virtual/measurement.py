"""From the model's FRFs to what a test system records: noise, or a full impact test.

Two routes:

* ``noisy_frfs``: the exact accelerance with a relative error and a floor, as
  complex Gaussian noise (the planner's noise model, DESIGN.md).
* ``impact_test``: what a lab does. A half-sine force pulse of duration τ hits
  the body at rest; the responses are computed in time, noise is added to the
  force and response channels, both are windowed (force window, exponential
  window), and H1 = Σ X F* / Σ |F|² over the averages is estimated with its
  coherence γ² = |Σ X F*|² / (Σ |X|² Σ |F|²).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Noise:
    """Measurement noise of an FRF: σ = relative·|H| + floor/m, complex Gaussian.

    ``floor`` is a fraction of 1/m (m the body's mass), like the planner's noise model.
    """

    relative: float = 0.01
    floor: float = 0.0


def noisy_frfs(H: np.ndarray, noise: Noise, mass: float, rng: np.random.Generator) -> np.ndarray:
    """H plus complex noise of standard deviation relative·|H| + floor/mass on each value."""
    sigma = noise.relative * np.abs(H) + noise.floor / mass
    return H + sigma * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape)) / np.sqrt(2)


@dataclass(frozen=True)
class ImpactTest:
    """An impact hammer test.

    Attributes
    ----------
    pulse : float
        Half-sine pulse duration τ, s (its spectrum falls to zero at 1.5/τ).
    peak : float
        Peak force, N.
    averages : int
        Hits per exciter averaged into H1.
    window_end : float
        Value of the exponential window at the end of the record.
    force_noise, response_noise : float
        Standard deviation of the noise on each channel, fraction of its RMS over the record.
    pretrigger : float
        Fraction of the record before the hit.
    force_window : float
        Fraction of the record after the hit kept by the force window (the rest is set to zero);
        it must hold the ringing of the band-limited pulse.
    """

    pulse: float = 0.5e-3
    peak: float = 200.0
    averages: int = 5
    window_end: float = 0.01
    force_noise: float = 0.002
    response_noise: float = 0.005
    pretrigger: float = 0.01
    force_window: float = 0.05


def half_sine_spectrum(f: np.ndarray, start: float, duration: float, peak: float) -> np.ndarray:
    """Fourier transform (N·s) of f(t) = peak·sin(π (t − start)/τ) for start ≤ t ≤ start + τ.

    F(ω) = peak (π/τ) (1 + e^{−iωτ}) e^{−iω·start} / ((π/τ)² − ω²), whose limit at ω = π/τ is
    −i·peak·τ/2 (times the shift); its first zero is at f = 1.5/τ.
    Sampling the band-limited pulse through this spectrum is what the anti-aliasing filter of
    the acquisition does to a pulse shorter than a sample.
    """
    w = 2 * np.pi * np.asarray(f, dtype=float)
    a = np.pi / duration
    near = np.isclose(w, a, rtol=1e-9)
    safe = np.where(near, 0.0, w)
    F = peak * a * (1 + np.exp(-1j * safe * duration)) / (a**2 - safe**2)
    F = np.where(near, -0.5j * peak * duration, F)
    return F * np.exp(-1j * w * start)


def exponential_window(n: int, end: float) -> np.ndarray:
    """w(t) = exp(−t/τ_w) over n samples, with w = ``end`` at the last one."""
    return end ** (np.arange(n) / (n - 1))


def impact_test(
    accelerance: Callable[[np.ndarray], np.ndarray],
    n_sensors: int,
    n_exciters: int,
    fmax: float,
    lines: int,
    test: ImpactTest,
    rng: np.random.Generator,
    padding: int = 8,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """H1 FRFs and coherence from simulated hits.

    Parameters
    ----------
    accelerance : callable
        f (Hz, array) → H (n_s, n_e, n_f), the system's accelerance.
    fmax, lines : float, int
        Analysis bandwidth (Hz) and number of spectral lines: Δf = fmax/lines, fs = 2.56 fmax.
    padding : int
        The response is computed over ``padding`` records and the first kept, so it starts
        from rest rather than wrapping around.

    Returns
    -------
    frequencies (lines,) Hz, H1 (n_s, n_e, lines) (m/s²)/N, coherence (n_s, n_e, lines).
    """
    df = fmax / lines
    fs = 2.56 * fmax
    n = int(round(fs / df))
    f_long = np.fft.rfftfreq(n * padding, 1 / fs)
    H_long = accelerance(np.maximum(f_long, 1e-6 * df))
    start = test.pretrigger * n / fs
    F_long = fs * half_sine_spectrum(f_long, start, test.pulse, test.peak)
    force = np.fft.irfft(F_long, n=n * padding)[:n]
    w = exponential_window(n, test.window_end)
    keep = (np.arange(n) / fs) <= start + max(4 * test.pulse, test.force_window * n / fs)
    f = np.fft.rfftfreq(n, 1 / fs)[1 : lines + 1]
    H1 = np.empty((n_sensors, n_exciters, lines), dtype=complex)
    coherence = np.empty(H1.shape)
    for j in range(n_exciters):
        response = np.fft.irfft(H_long[:, j] * F_long, n=n * padding, axis=-1)[:, :n]
        Sxf, Sxx, Sff = 0.0, 0.0, 0.0
        for _ in range(test.averages):
            f_meas = force + test.force_noise * np.sqrt(np.mean(force**2)) * rng.normal(size=n)
            x_meas = response + test.response_noise * np.sqrt(np.mean(response**2, axis=1))[:, None] * rng.normal(
                size=response.shape
            )
            F = np.fft.rfft(f_meas * keep * w)[1 : lines + 1]
            X = np.fft.rfft(x_meas * w, axis=-1)[:, 1 : lines + 1]
            Sxf, Sxx, Sff = Sxf + X * F.conj(), Sxx + np.abs(X) ** 2, Sff + np.abs(F) ** 2
        H1[:, j] = Sxf / Sff
        coherence[:, j] = np.abs(Sxf) ** 2 / (Sxx * Sff)
    return f, H1, coherence
